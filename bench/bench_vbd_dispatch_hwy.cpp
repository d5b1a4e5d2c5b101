// VBD's lanes kernels (src/integrators/vbd_lanes_kernel.hpp) dispatched by Highway (Debian's
// libhwy-dev) instead of vbd_lanes.cpp's table: the same kernel source compiled once per
// Highway target by foreach_target.h (8 lanes for the AVX-512 targets, 4 for AVX2, 2 below),
// each call going through HWY_DYNAMIC_DISPATCH. Benchmark-only: bench_vbd_sweep.cpp measures
// it against the table (BM_VbdDispatch) and checks that both give the same bits.
#include <immintrin.h>

#include <cstdint>
#include <type_traits>

#include "integrators/vbd_lanes_data.hpp"

#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "bench_vbd_dispatch_hwy.cpp"
#include <hwy/foreach_target.h>  // re-includes this file once per target
#include <hwy/highway.h>

HWY_BEFORE_NAMESPACE();
#define MAILLE_VBD_LANES_NAMESPACE HWY_NAMESPACE
#include "integrators/vbd_lanes_kernel.hpp"
#undef MAILLE_VBD_LANES_NAMESPACE
namespace maille::vbd_lanes::HWY_NAMESPACE {
#if HWY_TARGET <= HWY_AVX3
constexpr int kWidth = 8;
#elif HWY_TARGET == HWY_AVX2
constexpr int kWidth = 4;
#else
constexpr int kWidth = 2;
#endif
int Width() {
  return kWidth;
}
void Terms(const Block& b, const Rows& rows, const Step& s, Real* g, Real* h) {
  block_terms<kWidth>(b, rows, s, g, h);
}
void Solve(const std::uint32_t* points, std::uint32_t lanes, const Real* g, const Real* h,
           Real* out) {
  block_solve<kWidth>(points, lanes, g, h, out);
}
}  // namespace maille::vbd_lanes::HWY_NAMESPACE
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
namespace maille::vbd_lanes {
HWY_EXPORT(Width);
HWY_EXPORT(Terms);
HWY_EXPORT(Solve);

// HWY_DYNAMIC_DISPATCH at the call, as code written for Highway would call the kernel.
void highway_terms(const Block& b, const Rows& rows, const Step& s, Real* g, Real* h) {
  HWY_DYNAMIC_DISPATCH(Terms)(b, rows, s, g, h);
}

namespace {
void dispatch_terms(const Block& b, const Rows& rows, const Step& s, Real* g, Real* h) {
  HWY_DYNAMIC_DISPATCH(Terms)(b, rows, s, g, h);
}
void dispatch_solve(const std::uint32_t* points, std::uint32_t lanes, const Real* g, const Real* h,
                    Real* out) {
  HWY_DYNAMIC_DISPATCH(Solve)(points, lanes, g, h, out);
}
}  // namespace

// The kernels as a table row whose entries dispatch through Highway at every call.
const Kernels* highway_kernels() {
  static const Kernels k{HWY_DYNAMIC_DISPATCH(Width)(), &dispatch_terms, &dispatch_solve};
  return &k;
}
// Highway's best target on this CPU among those compiled (the lowest bit is the best), for the
// benchmark's label.
const char* highway_target() {
  const std::int64_t targets = hwy::SupportedTargets() & HWY_TARGETS;
  return hwy::TargetName(targets & -targets);
}
}  // namespace maille::vbd_lanes
#endif
