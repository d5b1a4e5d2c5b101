// The lanes kernels of vertex block descent at 2 lanes (vbd_lanes_kernel.hpp): SSE2, which
// every x86-64 CPU has (the build's own instruction set).
#include "vbd_lanes_kernel.hpp"

MAILLE_VBD_LANES_KERNELS(2)

// 8 lanes in SSE2 (each vector operation split by the compiler): the 8-lane layout on any CPU,
// for the tests of a CPU without AVX-512 (set_vbd_lane_width_portable).
namespace maille::vbd_lanes {
extern const Kernels kKernels8Portable;
const Kernels kKernels8Portable = {8, &block_terms<8>, &block_solve<8>};
}  // namespace maille::vbd_lanes
