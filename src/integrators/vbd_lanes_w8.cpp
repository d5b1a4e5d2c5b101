// The lanes kernels of vertex block descent at 8 lanes (vbd_lanes_kernel.hpp), compiled with
// -mavx512f (src/CMakeLists.txt) and run only where the CPU has AVX-512F (vbd_lanes.cpp).
#include "vbd_lanes_kernel.hpp"

MAILLE_VBD_LANES_KERNELS(8)
