// The structured kernel's layout: the links of a regular grid (structural, shear and bend links
// of a flag, a net, a cloth) found by neighbour offset, stored contiguously row by row, and run
// as contiguous vector loops without index arrays. Private to the CPU executor, like
// cpu_schedule.hpp: a pool whose kind opts in (`static constexpr bool grid_stencil = true`)
// stores these links first, in this order, and runs the others through its CpuSchedule.
//
// A grid link is one whose first end a is point (i, j) of a grid and whose second end is
// (i + di, j + dj) of the same grid for one of the families below (the orientation the grid
// builders use). Links of one family along one row that follow each other (a hole breaks the
// row) form a segment: ends a + k, b + k and storage slot + k for k < count. Parameters stay in
// the pool, one record per link; a segment whose records are all equal (bit for bit) is run
// with its first record as a constant (one load instead of one per link), which gives the same
// bits as reading each record.
//
// Forces (structured_forces, src/core/link_loops.cpp) go row by row: the links whose first end is
// in row j into a row buffer per family (zero where there is no link), then each point of row j
// sums, in one fixed order, the forces of its links as first end (row j's buffers) and as second
// end (the buffers of rows j, j - 1 and j - 2, read at the column offset of each family): a gather,
// no scatter, so the sum of a point does not depend on how rows are split among threads. Once
// row j is summed it is complete (no later row's link reaches it), so a caller may finish it at
// once (RowHook: fields, the wind and the kick-drift update, the fused step of
// simulator_fused.cpp). The threads take strips of rows; a strip computes the two link rows
// above it (its halo) and its own last two (which read the next strip's first rows) before a
// barrier, so that no strip reads positions another has already moved (RowHook::strip lets the
// caller do the same: the wind's cells, src/core/wind_rows.hpp).
//
// The implicit solvers run the links by segment (for_each_segment in src/core/schedule_loops.hpp):
// rows are cut into blocks of at least two rows, about kBlocks per grid; blocks of even rank run
// together, then those of odd rank, so no two blocks running at once touch one point.
#pragma once

#include <array>
#include <cstdint>
#include <span>
#include <utility>
#include <vector>

#include "maille/link_kind.hpp"

namespace maille {

// A regular grid of points as the grid builders lay them out: point first + j nx + i is (i, j)
// for i < nx, j < ny.
struct PointGrid {
  std::uint32_t first = 0;
  std::uint32_t nx = 0, ny = 0;
};

}  // namespace maille

namespace maille::detail {

class StructuredGrid {
 public:
  // (di, dj) from the first end: structural (2), shear (2), bend (2).
  static constexpr std::array<std::array<int, 2>, 6> kFamilies{
      {{1, 0}, {0, 1}, {1, 1}, {-1, 1}, {2, 0}, {0, 2}}};
  static constexpr std::uint32_t kBlocks = 16;  // per grid, at most

  // Called inside the strips: `strip` (may be null) by each thread that takes rows r0 .. r1 - 1
  // of grid g, before the barrier (rows r0 - 1 and r1 are other strips', still at t_n);
  // `run` on each finished row of points (row j of grid g).
  struct RowHook {
    void (*strip)(void* context, std::size_t g, std::uint32_t r0, std::uint32_t r1) = nullptr;
    void (*run)(void* context, std::size_t g, std::uint32_t j) = nullptr;
    void* context = nullptr;
  };

  struct Segment {
    std::uint32_t a = 0;      // first end of the first link
    std::uint32_t b = 0;      // second end of the first link
    std::uint32_t slot = 0;   // storage slot of the first link
    std::uint32_t count = 0;  // links: (a + k, b + k) in slot + k, k < count
  };

  // Step 1: the positions in `ends` of the grid links, in the order they are to be stored
  // (valid until the next call); `others` receives the other positions, in increasing order.
  std::span<const std::uint32_t> select(std::span<const LinkEnds> ends,
                                        std::span<const PointGrid> grids,
                                        std::vector<std::uint32_t>& others);
  // Step 2, once the pool stored the selected links first (slots 0 .. size() - 1): segments and
  // blocks. `same(s, t)`: the records of slots s and t are equal bit for bit.
  template <class Same>
  void build(std::span<const LinkEnds> ends, Same&& same) {
    cut_segments(ends);
    find_uniform(same);
  }
  // Which segments may run on one record (after a parameter edit).
  template <class Same>
  void find_uniform(Same&& same) {
    uniform_.assign(segments_.size(), 1);
    for (std::size_t s = 0; s < segments_.size(); ++s)
      for (std::uint32_t k = 1; k < segments_[s].count && uniform_[s]; ++k)
        uniform_[s] = same(segments_[s].slot, segments_[s].slot + k);
  }
  // The record of `slot` may have changed: its segment reads records one by one from now on.
  void edited(std::uint32_t slot);
  void clear();
  void release_scratch();

  std::size_t size() const { return links_; }  // links stored first
  std::span<const PointGrid> grids() const { return grids_; }
  // Segments of grid g's row j, family f: [first, second).
  std::pair<std::uint32_t, std::uint32_t> row_segments(std::size_t g, std::uint32_t j,
                                                       std::size_t f) const {
    const std::size_t r = (std::size_t(row_base_[g]) + j) * kFamilies.size() + f;
    return {row_segment_[r], row_segment_[r + 1]};
  }
  // Bit f set: family f has links in grid g. The kernel neither writes nor sums an absent
  // family's row buffers (a net has two families of the six).
  std::uint8_t families(std::size_t g) const { return present_[g]; }
  // Row buffers: a link row holds, per family and coordinate, width() values for the columns
  // -2 .. nx + 1 of the widest grid (column c at c + 2).
  std::size_t width() const { return width_; }
  std::size_t link_row_size() const { return kFamilies.size() * 3 * width_; }
  static constexpr std::size_t kRowsPerThread = 7;  // 3 rolling, 2 halo, 2 tail
  // Sizes the row buffers for `threads` threads; outside a parallel region only.
  void reserve(int threads) const;
  int reserved_threads() const { return reserved_; }
  Real* thread_rows(int thread) const {
    return scratch_.data() + link_row_size() * (1 + kRowsPerThread * std::size_t(thread));
  }
  const Real* zero_row() const { return scratch_.data(); }
  // The OpenMP team as seen from here (1 and 0 outside a parallel region).
  static int team_size();
  static int thread_index();
  const Segment& segment(std::size_t s) const { return segments_[s]; }
  bool uniform(std::size_t s) const { return uniform_[s] != 0; }

  // Block colour by block colour, the blocks of segments no two of which (of one colour)
  // touch one point (src/core/schedule_loops.hpp runs them): [first, end) of blocks.
  std::size_t colours() const { return colour_begin_.empty() ? 0 : colour_begin_.size() - 1; }
  std::pair<std::uint32_t, std::uint32_t> blocks_of_colour(std::size_t c) const {
    return {colour_begin_[c], colour_begin_[c + 1]};
  }
  std::pair<std::uint32_t, std::uint32_t> segments_of_block(std::size_t k) const {
    return {blocks_[k].begin, blocks_[k].end};
  }

 private:
  struct Block {
    std::uint32_t begin = 0, end = 0;  // segments
  };
  // A grid link's place: grid, block, row, family, column (sorted in this order).
  struct Key {
    std::uint32_t grid, block, row, family, column, position;
    auto tuple() const { return std::array{grid, block, row, family, column, position}; }
  };
  void cut_segments(std::span<const LinkEnds> ends);

  std::size_t links_ = 0;
  std::vector<Segment> segments_;            // storage order
  std::vector<std::uint8_t> uniform_;        // [segments] 1: every record equals the first
  std::vector<Block> blocks_;                // by colour
  std::vector<std::uint32_t> colour_begin_;  // colour c spans blocks_[begin[c] .. begin[c + 1])
  std::vector<PointGrid> grids_;             // the grids kept, by first point
  std::vector<std::uint32_t> row_base_;      // [grids] rows of the grids before
  std::vector<std::uint32_t> row_segment_;   // [rows x families + 1] segments by row, family
  std::vector<std::uint8_t> present_;        // [grids] bit f: family f has a link there
  std::size_t width_ = 0;
  // Row buffers: a zero link row, then kRowsPerThread link rows per thread.
  mutable std::vector<Real> scratch_;
  mutable int reserved_ = 0;
  // Scratch of select(): the keys and order of the selected links, each one's block id.
  std::vector<Key> keys_;
  std::vector<std::uint32_t> order_;
  std::vector<std::uint32_t> block_of_;      // [selected links, storage order] global block id
  std::vector<std::uint32_t> block_colour_;  // [global blocks] 0 or 1
};

}  // namespace maille::detail
