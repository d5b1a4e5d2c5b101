// The wind on grid faces (Surface::grids), row by row: the pieces shared by the wind stage
// (field_forces.cpp, which runs them by tiles of rows) and the fused grid step (wind_rows.cpp,
// which runs them inside the structured kernel's rows). Compiled once (wind_grid.cpp), so both
// callers run the same machine code on the same values and get the same bits.
//
// A tile is up to grid_tile points of a row, i0 .. i0 + width - 1. A row of a tile (GridRow) is
// a copy of points i0 - 1 .. i0 - 1 + cells in struct-of-arrays form (k = i - i0 + 1); where the
// grid has no such point (left of its first column, right of its last, the padding) the row
// repeats its neighbour, so the cell there is degenerate (a2 = 0 exactly) and gets no force,
// and every row of a tile runs the same cells with no test. The cells between two rows of a
// tile (CellRow) hold the force on each corner of both faces of each cell:
//
//      row j+1   d ----- c            point (i, j) is corner of: F0, F1 of cell (i, j),
//                |  F1 / |            F0 of cell (i-1, j), F0 and F1 of cell (i-1, j-1),
//                |   /   |            F1 of cell (i, j-1); cells outside the grid count 0.
//                | / F0  |
//      row j     a ----- b            F0 = (a, b, c), F1 = (a, c, d)
//
// A cell's force is a pure function of its corners' x and v, so a tile that recomputes a
// border cell gets its owner's bits.
#pragma once

#include <cstdint>

#include "gust.hpp"
#include "maille/model.hpp"

namespace maille::wind_grid {

constexpr std::int64_t grid_tile = 64;

struct WindLaw {
  gust::Basis basis;
  Real coef = 0;  // rho C_d / 12 (gust::face_force)
};

inline WindLaw law(const WindField& w, double t) {
  return {gust::basis(w, t), w.density * w.drag_coefficient / Real(12)};
}

// A tile of width points runs the cells i0 - 1 .. i0 + width - 1 (k = i - i0 + 1), padded to a
// multiple of 4 cells so that the vectorised loops have no scalar remainder.
constexpr std::int64_t padded_cells(std::int64_t width) {
  return (width + 1 + 3) / 4 * 4;
}
constexpr std::int64_t cell_cap = padded_cells(grid_tile);
constexpr std::int64_t face_cap = 2 * cell_cap;

// One row of a tile: x and v by axis.
struct GridRow {
  alignas(64) Real x[3][cell_cap + 1];
  alignas(64) Real v[3][cell_cap + 1];  // a third of each velocity: a face's mean is their sum
  // With gusts: a third of each point's coordinates along and across the wind (gust::arguments),
  // so that a face's are the sum of its corners'.
  alignas(64) double s[cell_cap + 1];
  alignas(64) double q[cell_cap + 1];
};
// One row of the cells of a tile: the force on each corner of F0 at [axis][k] and of F1 at
// [axis][cells + k].
struct CellRow {
  alignas(64) Real f[3][face_cap];
};
// The gust at the faces of one row of cells (indexed as CellRow) or of a block of loose faces.
struct GustBuffers {
  alignas(64) float r[4][face_cap];     // the four reduced arguments, turns
  alignas(64) float gust[3][face_cap];  // w - U at the centre, m/s
};

// The gust at faces [0, n) from their reduced arguments (gb.r) into gb.gust: float only.
void gust_sines(const gust::Basis& basis, std::int64_t n, GustBuffers& gb);

// Row j of the tile [i0, i0 + width) of grid g into r.
template <bool Gusty>
void load_row(const WindLaw& law, const FaceGrid& g, std::int64_t i0, std::int64_t width,
              std::int64_t j, const Vec3* x, const Vec3* v, GridRow& r);

// The cells k in [0, cells) between rows lo and hi into out (cells = padded_cells(width));
// returns how many faces of the cells k >= 1 are not degenerate (cell 0 is the left neighbour
// tile's or a ghost).
template <bool Gusty>
std::uint64_t cell_row(const WindLaw& law, const GridRow& lo, const GridRow& hi, std::int64_t cells,
                       CellRow& out);

// A row of cells outside the grid (below its first row, above its last).
void zero_cells(CellRow& r);

// Points i0 .. i0 + width - 1 of one row (f points at i0): f += the forces of their six faces,
// from the cells below the row and above it.
void add_row(const CellRow& below, const CellRow& above, std::int64_t width, Vec3* f);

}  // namespace maille::wind_grid
