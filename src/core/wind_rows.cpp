#include "wind_rows.hpp"

#include <algorithm>

namespace maille::detail {

namespace {

bool same(const FaceGrid& f, const PointGrid& p) {
  return f.first == p.first && f.nx == p.nx && f.ny == p.ny;
}

// The tile [i0, i0 + width) of row tile t (field_forces.cpp's split of a row).
struct Tile {
  std::int64_t i0, width, cells;
};
Tile tile(const FaceGrid& g, std::int64_t t) {
  const std::int64_t i0 = t * wind_grid::grid_tile;
  const std::int64_t width = std::min<std::int64_t>(wind_grid::grid_tile, g.nx - i0);
  return {i0, width, wind_grid::padded_cells(width)};
}

std::int64_t tiles(const FaceGrid& g) {
  return (std::int64_t(g.nx) + wind_grid::grid_tile - 1) / wind_grid::grid_tile;
}

}  // namespace

bool WindRows::covers(const Model& m, std::span<const PointGrid> grids) {
  if (!m.surface.loose.empty()) return false;
  for (const FaceGrid& f : m.surface.grids)
    if (std::none_of(grids.begin(), grids.end(), [&](const PointGrid& p) { return same(f, p); }))
      return false;
  return true;
}

void WindRows::begin(const Model& m, std::span<const PointGrid> grids, double t, int threads) {
  law_ = wind_grid::law(m.fields.wind, t);
  faces_.assign(grids.size(), nullptr);
  std::size_t tiles_needed = 0;
  for (std::size_t g = 0; g < grids.size(); ++g)
    for (const FaceGrid& f : m.surface.grids)
      if (same(f, grids[g])) {
        faces_[g] = &f;
        tiles_needed = std::max(tiles_needed, std::size_t(tiles(f)));
      }
  const auto count = std::size_t(std::max(threads, 1));
  if (threads_.size() < count) threads_.resize(count);
  for (Thread& th : threads_) th.pushed = 0;
  const std::size_t team = threads_.size();
  if (tiles_needed > tiles_ || cell_rows_.size() < team * (kRing + 2) * tiles_) {
    tiles_ = std::max(tiles_, tiles_needed);
    cell_rows_.resize(team * (kRing + 2) * tiles_);
    grid_rows_.resize(team * 2 * tiles_);
  }
}

std::uint64_t WindRows::pushed() const {
  std::uint64_t n = 0;
  for (const Thread& th : threads_) n += th.pushed;
  return n;
}

void WindRows::strip(const FaceGrid& g, std::uint32_t r0, std::uint32_t r1, const Vec3* x,
                     const Vec3* v) {
  if (law_.basis.steady)
    strip<false>(g, r0, r1, x, v);
  else
    strip<true>(g, r0, r1, x, v);
}

void WindRows::row(const FaceGrid& g, std::uint32_t j, const Vec3* x, const Vec3* v, Vec3* f) {
  if (law_.basis.steady)
    row<false>(g, j, x, v, f);
  else
    row<true>(g, j, x, v, f);
}

// The halo (cells between r0 - 1 and r0: the strip below's, not counted) and the tail (cells
// between r1 - 1 and r1: this strip's, counted); zero outside the grid.
template <bool Gusty>
void WindRows::strip(const FaceGrid& g, std::uint32_t r0, std::uint32_t r1, const Vec3* x,
                     const Vec3* v) {
  const int t = StructuredGrid::thread_index();
  Thread& th = threads_[std::size_t(t)];
  th.r0 = r0, th.r1 = r1;
  for (std::int64_t k = 0; k < tiles(g); ++k) {
    const Tile tl = tile(g, k);
    wind_grid::GridRow& lo = points(t, 0, k);
    wind_grid::GridRow& hi = points(t, 1, k);
    auto cells_between = [&](std::int64_t j, wind_grid::CellRow& out) {
      wind_grid::load_row<Gusty>(law_, g, tl.i0, tl.width, j, x, v, lo);
      wind_grid::load_row<Gusty>(law_, g, tl.i0, tl.width, j + 1, x, v, hi);
      return wind_grid::cell_row<Gusty>(law_, lo, hi, tl.cells, out);
    };
    if (r0 > 0)
      cells_between(std::int64_t(r0) - 1, cells(t, kHalo, k));
    else
      wind_grid::zero_cells(cells(t, kHalo, k));
    if (r1 < g.ny)
      th.pushed += cells_between(std::int64_t(r1) - 1, cells(t, kTail, k));
    else
      wind_grid::zero_cells(cells(t, kTail, k));
  }
}

// Row j: the ring's slot j % 2 takes the cells above it, the row of points j + 1 is loaded into
// points slot (j + 1) % 2 (row j's is there from the row before, or loaded at the strip's first).
template <bool Gusty>
void WindRows::row(const FaceGrid& g, std::uint32_t j, const Vec3* x, const Vec3* v, Vec3* f) {
  const int t = StructuredGrid::thread_index();
  Thread& th = threads_[std::size_t(t)];
  const int here = int(j % 2), next = 1 - here;
  for (std::int64_t k = 0; k < tiles(g); ++k) {
    const Tile tl = tile(g, k);
    const wind_grid::CellRow& below = j == th.r0 ? cells(t, kHalo, k) : cells(t, kRing + next, k);
    wind_grid::CellRow* above = &cells(t, kTail, k);
    if (j + 1 < th.r1) {
      if (j == th.r0)
        wind_grid::load_row<Gusty>(law_, g, tl.i0, tl.width, j, x, v, points(t, here, k));
      wind_grid::load_row<Gusty>(law_, g, tl.i0, tl.width, std::int64_t(j) + 1, x, v,
                                 points(t, next, k));
      above = &cells(t, kRing + here, k);
      th.pushed += wind_grid::cell_row<Gusty>(law_, points(t, here, k), points(t, next, k),
                                              tl.cells, *above);
    }
    wind_grid::add_row(below, *above, tl.width, f + g.first + std::int64_t(j) * g.nx + tl.i0);
  }
}

}  // namespace maille::detail
