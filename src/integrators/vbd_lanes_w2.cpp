// The lanes kernels of vertex block descent at 2 lanes (vbd_lanes_kernel.hpp): SSE2, which
// every x86-64 CPU has.
#include "vbd_lanes_kernel.hpp"

MAILLE_VBD_LANES_KERNELS(2)
