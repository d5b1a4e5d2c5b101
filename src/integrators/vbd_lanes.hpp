// Internal: vertex block descent's sweeps in SIMD lanes, one point per lane (implicit_vbd.cpp
// calls it; docs/implicit.md, "Where a VBD step's time goes").
//
// The points of one colour go in blocks of W (2 with SSE2, 4 with AVX2, 8 with AVX-512F, chosen
// at run time for the CPU), and each block's links in the leading always-active spring-damper
// pools are laid out as padded adjacency: row k holds the k-th link of every lane's point (its
// other end and its parameters), a point with fewer links padded with a link to itself of zero
// stiffness, rest length and damping, which adds exactly +0.0 to sums that are never -0.0. A
// block's g and H (inertia, drag, those pools) are computed in lanes, the other terms (later
// pools, this step's contact links, point-triangle and point contacts) added by the scalar code
// for the same points, and the 3x3 solves run in lanes. Every lane runs the scalar sweep's
// operations in its order, so the result is the scalar sweep's, bit for bit, at every width
// (tests/unit/test_vbd_lanes.cpp).
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "maille/link_pool.hpp"
#include "vbd_lanes_data.hpp"

namespace maille {

// Widths: 1 is the scalar sweep (the reference); 2, 4, 8 lanes where the build and the CPU can
// run them. The width in use is the widest the CPU runs, unless the environment variable
// MAILLE_VBD_LANES (1, 2, 4 or 8, read once) or set_vbd_lane_width (tests, benchmarks) says
// another.
bool vbd_lane_width_runs(int width);
int vbd_lane_width();
// Forces a width for the VBD solvers' next steps (0: back to the default); false, and nothing
// changed, for a width this CPU or build cannot run.
bool set_vbd_lane_width(int width);
// Forces 8 lanes compiled for the build's own instruction set (the compiler splits each vector
// operation), which any x86-64 CPU runs: the tests' check of the 8-lane layout on a CPU without
// AVX-512 (the instructions differ, the operations and their order do not). False where there
// are no lanes; set_vbd_lane_width undoes it.
bool set_vbd_lane_width_portable();
// Runs `kernels` (their width) instead of the table's until called again with null: the
// benchmark of another dispatch of the same kernels (bench/bench_vbd_dispatch_hwy.cpp). The
// caller keeps them alive; set_vbd_lane_width does not undo it.
void set_vbd_lane_kernels(const vbd_lanes::Kernels* kernels);
// The kernels of the width in use (null: the scalar sweep).
const vbd_lanes::Kernels* vbd_lane_kernels();

// One model pool's links by point, as VBD keeps them (PoolRows).
struct LanePoolRows {
  const LinkPoolBase* pool = nullptr;
  const std::uint32_t* row = nullptr;    // [points + 1]
  const std::uint32_t* slots = nullptr;  // storage slots by point
};

class VbdLanes {
 public:
  // Whether a pool can run in lanes: always active, of a kind whose VBD terms the kernels
  // compute (SpringDamper::axial).
  static bool runs(const LinkPoolBase& pool);

  // Lays out the blocks of every colour (colour_row into by_colour, VBD's colouring) and the
  // padded adjacency of `pools` (a prefix of VBD's pools that all run), for the width in use.
  // Keeps its buffers' capacity: allocates only when the layout grows.
  void arrange(std::span<const LanePoolRows> pools, std::span<const std::uint32_t> colour_row,
               std::span<const std::uint32_t> by_colour);
  // Copies the pools' parameters into the rows again (they may be edited between steps).
  void refresh_params();
  // Lanes in use (0: the scalar sweep; nothing arranged).
  int width() const { return kernels_ ? kernels_->width : 0; }
  // How many of VBD's pools (from the first) the lanes take.
  std::size_t pools() const { return pools_.size(); }
  // Whether the layout was made for the width in use (set_vbd_lane_width may change it).
  bool current() const;

  // For the `count` points by_colour[colour_row[c] + offset ...] (offset a multiple of 64):
  // their g and H from the lane pools, into g (3 Reals per point) and h (9 Reals per point).
  void terms(std::uint32_t c, std::uint32_t offset, std::uint32_t count, const vbd_lanes::Step& s,
             Real* g, Real* h) const;
  // The same points' Newton steps H^-1 g into out[3 k + j] (k: the point's rank in the run).
  void solve(std::uint32_t c, std::uint32_t offset, std::uint32_t count, const Real* g,
             const Real* h, Real* out) const;

 private:
  vbd_lanes::Block block(std::size_t b) const;

  const vbd_lanes::Kernels* kernels_ = nullptr;
  int requested_ = 0;                                      // vbd_lane_width() when arranged
  const vbd_lanes::Kernels* requested_kernels_ = nullptr;  // and its kernels
  std::vector<LanePoolRows> pools_;
  std::vector<std::uint32_t> block_of_colour_;  // [colours + 1] first block of each colour
  std::vector<std::uint32_t> points_;           // [blocks * W]
  std::vector<std::uint32_t> lanes_;            // [blocks] real points
  std::vector<std::uint32_t> first_row_;        // [blocks]
  std::vector<std::uint32_t> depth_;            // [blocks * pools]
  std::vector<std::uint8_t> has_;               // [blocks * pools]
  std::vector<std::uint32_t> neighbour_;        // [rows * W]
  std::vector<std::uint32_t> slot_;             // [rows * W] the link's slot (padding: ~0)
  std::vector<std::uint8_t> pool_of_row_;       // [rows]
  std::vector<Real> params_;                    // [rows * 3 W]
};

}  // namespace maille
