// The wind on grid faces inside the fused grid step (simulator_fused.cpp): the structured
// kernel finishes the rows of a grid one by one, and row j is integrated (x, v moved to t_{n+1})
// before row j + 1 is finished, so the wind on a row's six faces must be summed before it
// moves, from cells whose corners are all still at t_n:
// - the cells between rows j - 1 and j were computed when row j - 1 was finished (row j still
//   at t_n) and kept, a rolling buffer per thread;
// - the cells between rows j and j + 1 are computed when row j is finished (row j + 1 is the
//   same thread's, still at t_n); the last row of a strip reads the first of the next strip,
//   which another thread moves, so those cells (the strip's tail) are computed before the
//   kernel's barrier, as are the cells below the strip's first row (its halo): what the link
//   kernel does with its link rows.
// The pieces are the wind stage's (wind_grid.hpp, by tiles of grid_tile points: each tile of a
// row its own buffers), and each point sums its faces in the same order, so the fused step gives
// the unfused step's bits on one thread or two.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "maille/detail/structured_grid.hpp"
#include "maille/model.hpp"
#include "wind_grid.hpp"

namespace maille::detail {

class WindRows {
 public:
  // Whether every face the wind pushes is a face of one of `grids` (the structured kernel's):
  // no loose faces, each face grid one of them.
  static bool covers(const Model& m, std::span<const PointGrid> grids);

  // Before a fused step, outside parallel regions: the law at time t, the face grid of each of
  // `grids` (null where none), buffers for `threads` threads (they grow, never shrink: nothing
  // is allocated once they have the size), the counters cleared.
  void begin(const Model& m, std::span<const PointGrid> grids, double t, int threads);
  // The face grid of the kernel's grid g, or null.
  const FaceGrid* faces(std::size_t g) const { return faces_[g]; }
  // Inside the kernel, before its barrier, by the thread taking rows r0 .. r1 - 1 of g: the
  // cells below r0 and above r1 - 1.
  void strip(const FaceGrid& g, std::uint32_t r0, std::uint32_t r1, const Vec3* x, const Vec3* v);
  // Row j of g, its links summed into f, not yet moved: the cells above it (unless they are the
  // strip's tail), then f += the forces of each point's six faces.
  void row(const FaceGrid& g, std::uint32_t j, const Vec3* x, const Vec3* v, Vec3* f);
  // Faces pushed this step (not degenerate), all threads.
  std::uint64_t pushed() const;

 private:
  struct alignas(64) Thread {
    std::uint32_t r0 = 0, r1 = 0;  // the strip
    std::uint64_t pushed = 0;
  };
  enum Slot { kHalo, kTail, kRing };  // cell rows: halo, tail, then a ring of two
  wind_grid::CellRow& cells(int thread, int slot, std::int64_t tile) {
    return cell_rows_[(std::size_t(thread) * (kRing + 2) + std::size_t(slot)) * tiles_ +
                      std::size_t(tile)];
  }
  wind_grid::GridRow& points(int thread, int slot, std::int64_t tile) {
    return grid_rows_[(std::size_t(thread) * 2 + std::size_t(slot)) * tiles_ + std::size_t(tile)];
  }
  template <bool Gusty>
  void strip(const FaceGrid& g, std::uint32_t r0, std::uint32_t r1, const Vec3* x, const Vec3* v);
  template <bool Gusty>
  void row(const FaceGrid& g, std::uint32_t j, const Vec3* x, const Vec3* v, Vec3* f);

  wind_grid::WindLaw law_;
  std::vector<const FaceGrid*> faces_;  // [kernel grids]
  std::size_t tiles_ = 0;               // per row of the widest face grid
  std::vector<Thread> threads_;
  std::vector<wind_grid::CellRow> cell_rows_;  // [threads][halo, tail, ring 2][tiles]
  std::vector<wind_grid::GridRow> grid_rows_;  // [threads][ring 2][tiles]
};

}  // namespace maille::detail
