// The lanes kernels of vertex block descent at 2 lanes (src/integrators/vbd_lanes_kernel.hpp)
// for WebAssembly SIMD: the build has -msimd128, whose vectors hold 2 doubles, so GCC's vector
// extensions of width 2 become f64x2 operations. The same operations in the same order as the
// scalar sweep, so the same bits (the browser test's golden hashes of the VBD examples).
#include "integrators/vbd_lanes_kernel.hpp"

MAILLE_VBD_LANES_KERNELS(2)
