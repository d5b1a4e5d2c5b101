// The lanes kernels of vertex block descent at 4 lanes (vbd_lanes_kernel.hpp), compiled with
// -mavx2 (src/CMakeLists.txt) and run only where the CPU has AVX2 (vbd_lanes.cpp).
#include "vbd_lanes_kernel.hpp"

MAILLE_VBD_LANES_KERNELS(4)
