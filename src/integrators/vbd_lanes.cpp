// Vertex block descent in lanes (vbd_lanes.hpp): the layout of the blocks and the choice of the
// kernels' width for the CPU.
//
// Dispatch: the kernels are written once (vbd_lanes_kernel.hpp, GCC vector extensions with W a
// template parameter) and compiled once per width in their own translation unit with that
// width's instruction set (-mavx2, -mavx512f); the CPU is asked once (__builtin_cpu_supports)
// and a table of function pointers picked, so a build for any x86-64 runs 4 or 8 lanes where
// the CPU has them. GCC's target_clones was not used: a clone changes the instruction set of
// one function, not the data layout (the width is the block's shape), and inlining across
// target attributes is refused. Highway's dynamic dispatch of the same kernels
// (bench/bench_vbd_dispatch_hwy.cpp, through set_vbd_lane_kernels) gave the same bits at the
// same speed within noise (docs/implicit.md): the table stays, with no dependency more.
#include "vbd_lanes.hpp"

#include <algorithm>
#include <atomic>
#include <cstdlib>
#include <cstring>
#include <limits>

#include "maille/links/spring_damper.hpp"

#if defined(MAILLE_VBD_LANES_X86)
namespace maille::vbd_lanes {
extern const Kernels kKernels2, kKernels4, kKernels8, kKernels8Portable;
}
#elif defined(MAILLE_VBD_LANES_WASM)
namespace maille::vbd_lanes {
extern const Kernels kKernels2;  // WebAssembly SIMD, 2 doubles (web/src/vbd_lanes_simd128.cpp)
}
#endif

namespace maille {

namespace {

constexpr std::uint32_t kPadding = std::numeric_limits<std::uint32_t>::max();

std::atomic<int> g_forced{0};
std::atomic<bool> g_portable{false};                        // set_vbd_lane_width_portable
std::atomic<const vbd_lanes::Kernels*> g_kernels{nullptr};  // set_vbd_lane_kernels

const vbd_lanes::Kernels* kernels_of(int width) {
  if (const vbd_lanes::Kernels* k = g_kernels.load(std::memory_order_relaxed))
    return width == k->width ? k : nullptr;
#if defined(MAILLE_VBD_LANES_X86)
  if (width == 8 && g_portable.load(std::memory_order_relaxed))
    return &vbd_lanes::kKernels8Portable;
  switch (width) {
    case 2:
      return &vbd_lanes::kKernels2;
    case 4:
      return __builtin_cpu_supports("avx2") ? &vbd_lanes::kKernels4 : nullptr;
    case 8:
      return __builtin_cpu_supports("avx512f") ? &vbd_lanes::kKernels8 : nullptr;
    default:
      return nullptr;
  }
#elif defined(MAILLE_VBD_LANES_WASM)
  return width == 2 ? &vbd_lanes::kKernels2 : nullptr;
#else
  (void)width;
  return nullptr;
#endif
}

int widest() {
  for (const int w : {8, 4, 2})
    if (kernels_of(w)) return w;
  return 1;
}

// The environment's width (MAILLE_VBD_LANES), read once; 0 when unset or not runnable here.
int from_environment() {
  static const int width = [] {
    const char* e = std::getenv("MAILLE_VBD_LANES");
    if (!e) return 0;
    const int w = std::atoi(e);
    return vbd_lane_width_runs(w) ? w : 0;
  }();
  return width;
}

const LinkPool<SpringDamper>* spring_dampers(const LinkPoolBase& pool) {
  return dynamic_cast<const LinkPool<SpringDamper>*>(&pool);
}

}  // namespace

bool vbd_lane_width_runs(int width) {
  return width == 1 || kernels_of(width) != nullptr;
}

int vbd_lane_width() {
  if (const vbd_lanes::Kernels* k = g_kernels.load(std::memory_order_relaxed)) return k->width;
  if (const int forced = g_forced.load(std::memory_order_relaxed)) return forced;
  if (const int env = from_environment()) return env;
  static const int best = widest();
  return best;
}

bool set_vbd_lane_width(int width) {
  if (width != 0 && !vbd_lane_width_runs(width)) return false;
  g_forced.store(width, std::memory_order_relaxed);
  g_portable.store(false, std::memory_order_relaxed);
  return true;
}

const vbd_lanes::Kernels* vbd_lane_kernels() {
  return kernels_of(vbd_lane_width());
}

void set_vbd_lane_kernels(const vbd_lanes::Kernels* kernels) {
  g_kernels.store(kernels, std::memory_order_relaxed);
}

bool set_vbd_lane_width_portable() {
#if defined(MAILLE_VBD_LANES_X86)
  g_portable.store(true, std::memory_order_relaxed);
  g_forced.store(8, std::memory_order_relaxed);
  return true;
#else
  return false;
#endif
}

bool VbdLanes::runs(const LinkPoolBase& pool) {
  return !pool.conditional() && spring_dampers(pool) != nullptr;
}

bool VbdLanes::current() const {
  const int w = vbd_lane_width();
  return requested_ == w && requested_kernels_ == kernels_of(w);
}

void VbdLanes::arrange(std::span<const LanePoolRows> pools,
                       std::span<const std::uint32_t> colour_row,
                       std::span<const std::uint32_t> by_colour) {
  const int w = vbd_lane_width();
  requested_ = w;
  requested_kernels_ = kernels_of(w);
  kernels_ = pools.empty() || pools.size() > 255 ? nullptr : kernels_of(w);
  pools_.assign(pools.begin(), pools.end());
  if (!kernels_) return;
  const std::size_t W = std::size_t(w), P = pools.size();
  const std::size_t colours = colour_row.size() - 1;
  block_of_colour_.resize(colours + 1);
  std::size_t blocks = 0;
  for (std::size_t c = 0; c < colours; ++c) {
    block_of_colour_[c] = std::uint32_t(blocks);
    blocks += (colour_row[c + 1] - colour_row[c] + W - 1) / W;
  }
  block_of_colour_[colours] = std::uint32_t(blocks);
  points_.resize(blocks * W);
  lanes_.resize(blocks);
  first_row_.resize(blocks);
  depth_.resize(blocks * P);
  has_.resize(blocks * P);
  neighbour_.clear();
  slot_.clear();
  pool_of_row_.clear();
  std::size_t rows = 0;
  for (std::size_t c = 0; c < colours; ++c)
    for (std::size_t b = block_of_colour_[c]; b < block_of_colour_[c + 1]; ++b) {
      const std::size_t first = colour_row[c] + (b - block_of_colour_[c]) * W;
      const std::size_t lanes = std::min<std::size_t>(W, colour_row[c + 1] - first);
      std::uint32_t* pts = points_.data() + b * W;
      for (std::size_t l = 0; l < W; ++l) pts[l] = by_colour[first + (l < lanes ? l : 0)];
      lanes_[b] = std::uint32_t(lanes);
      first_row_[b] = std::uint32_t(rows);
      for (std::size_t q = 0; q < P; ++q) {
        const LanePoolRows& r = pools[q];
        const auto ends = r.pool->slot_ends();
        std::uint32_t depth = 0;
        std::uint8_t has = 0;
        for (std::size_t l = 0; l < lanes; ++l) {
          const std::uint32_t n = r.row[pts[l] + 1] - r.row[pts[l]];
          depth = std::max(depth, n);
          if (n > 0) has = std::uint8_t(has | (1u << l));
        }
        depth_[b * P + q] = depth;
        has_[b * P + q] = has;
        for (std::uint32_t k = 0; k < depth; ++k) {
          for (std::size_t l = 0; l < W; ++l) {
            const std::uint32_t i = pts[l];
            const bool link = l < lanes && k < r.row[i + 1] - r.row[i];
            const std::uint32_t slot = link ? r.slots[r.row[i] + k] : kPadding;
            const LinkEnds e = link ? ends[slot] : LinkEnds{i, i};
            neighbour_.push_back(e.a == i ? e.b : e.a);
            slot_.push_back(slot);
          }
          pool_of_row_.push_back(std::uint8_t(q));
        }
        rows += depth;
      }
    }
  params_.resize(rows * 3 * W);
  refresh_params();
}

void VbdLanes::refresh_params() {
  if (!kernels_) return;
  const std::size_t W = std::size_t(kernels_->width), rows = pool_of_row_.size();
  for (std::size_t r = 0; r < rows; ++r) {
    const auto par = spring_dampers(*pools_[pool_of_row_[r]].pool)->slot_params();
    Real* out = params_.data() + r * 3 * W;
    for (std::size_t l = 0; l < W; ++l) {
      const std::uint32_t slot = slot_[r * W + l];
      const SpringDamper::Params p = slot == kPadding ? SpringDamper::Params{} : par[slot];
      out[l] = p.stiffness;
      out[W + l] = p.rest_length;
      out[2 * W + l] = p.damping;
    }
  }
}

vbd_lanes::Block VbdLanes::block(std::size_t b) const {
  const std::size_t W = std::size_t(kernels_->width), P = pools_.size();
  return {points_.data() + b * W, lanes_[b],          first_row_[b], std::uint32_t(P),
          depth_.data() + b * P,  has_.data() + b * P};
}

void VbdLanes::terms(std::uint32_t c, std::uint32_t offset, std::uint32_t count,
                     const vbd_lanes::Step& s, Real* g, Real* h) const {
  const std::uint32_t W = std::uint32_t(kernels_->width);
  const vbd_lanes::Rows rows{neighbour_.data(), params_.data()};
  const std::uint32_t first = block_of_colour_[c] + offset / W;
  for (std::uint32_t b = first; b < first + (count + W - 1) / W; ++b)
    kernels_->terms(block(b), rows, s, g, h);
}

void VbdLanes::solve(std::uint32_t c, std::uint32_t offset, std::uint32_t count, const Real* g,
                     const Real* h, Real* out) const {
  const std::uint32_t W = std::uint32_t(kernels_->width);
  const std::uint32_t first = block_of_colour_[c] + offset / W;
  for (std::uint32_t b = first, k = 0; k < count; ++b, k += W)
    kernels_->solve(points_.data() + std::size_t(b) * W, lanes_[b], g, h, out + 3 * k);
}

}  // namespace maille
