#include <algorithm>
#include <cmath>
#include <cstdint>
#include <utility>

#include "gust.hpp"
#include "point_update.hpp"
#include "stages.hpp"
#include "wind_grid.hpp"

namespace maille::stages {

namespace {

// f += m g - gamma m v, on free points only (fixed points would ignore it anyway).
void point_fields(const Model& m, State& s) {
  const Vec3 g = m.fields.gravity;
  const Real gamma = m.fields.air_drag;
  const Real* mass = m.points.mass.data();
  const Real* inv_mass = m.points.inv_mass.data();
  const Vec3* v = s.v().data();
  Vec3* f = s.f().data();
  const auto n = static_cast<std::int64_t>(s.size());
#pragma omp for schedule(static)
  for (std::int64_t i = 0; i < n; ++i)
    f[i] += point_update::field_force(g, gamma, mass[i], inv_mass[i], v[i]);
}

// Wind pressure on each face (see WindField and gust::face_force), in two parts:
//
// Grids (Surface::grids, the flag's faces): row by row, in tiles of up to grid_tile points of a
// row (the pieces and the cell diagram: wind_grid.hpp; the fused grid step runs the same pieces
// inside its rows: wind_rows.hpp). Per tile, a row of points is copied into struct-of-arrays
// buffers on the stack (with each point's coordinates along and across the wind when there are
// gusts), the row of cells between it and the next is computed by vectorised loops with
// contiguous loads only (the gust's arguments of both faces of each cell, double; the sines,
// float; geometry and force of both faces, float, into a buffer), and each point of the row
// sums the forces of its six faces from that row of cells and the one below.
//
// No point is written twice, so there is no colouring and no read-modify-write chain, and a
// point's sum has the same order whatever the tiles. Tiles and strips of rows split the work
// among threads; a tile recomputes the cells of its left and bottom borders (a pure function of
// x and v, so the same bits as their owner's) and counts only its own.
//
// Other faces (Surface::loose, coloured so that no two in a group share a corner): blocks of
// faces in three passes over small buffers: gather (scalar: indexed loads of 24-byte Vec3s do
// not vectorise well), force (vectorised), scatter to the corners (scalar: a vectorised loop
// cannot know that faces of one colour share no corner).
//
// The gust field was 80 % of the default scene's step before; docs/benchmarks.md has the story.
constexpr std::int64_t wind_block = 64;

using wind_grid::CellRow;
using wind_grid::grid_tile;
using wind_grid::GridRow;
using wind_grid::GustBuffers;
using wind_grid::padded_cells;
using wind_grid::WindLaw;
static_assert(wind_grid::face_cap >= wind_block);

// The reduced arguments of faces [0, n) from their centres (m, by axis) into gb.r.
void gust_arguments(const gust::Basis& basis, const Real* __restrict px, const Real* __restrict py,
                    const Real* __restrict pz, std::int64_t n, GustBuffers& gb) {
  float* __restrict r0 = gb.r[0];
  float* __restrict r1 = gb.r[1];
  float* __restrict r2 = gb.r[2];
  float* __restrict r3 = gb.r[3];
  for (std::int64_t j = 0; j < n; ++j) {
    float r[4];
    gust::arguments(basis, Vec3{px[j], py[j], pz[j]}, r);
    r0[j] = r[0], r1[j] = r[1], r2[j] = r[2], r3[j] = r[3];
  }
}

template <bool Gusty>
inline Vec3 air(const gust::Basis& b, const GustBuffers& gb, std::int64_t j) {
  return Gusty ? b.mean + Vec3{Real(gb.gust[0][j]), Real(gb.gust[1][j]), Real(gb.gust[2][j])}
               : b.mean;
}

// Tile [i0, i0 + width) x rows [j0, j1) of grid g (wind_grid.hpp's pieces).
template <bool Gusty>
std::uint64_t wind_grid_tile(const WindLaw& law, const FaceGrid& g, std::int64_t i0,
                             std::int64_t width, std::int64_t j0, std::int64_t j1, const Vec3* x,
                             const Vec3* v, Vec3* f) {
  using wind_grid::cell_row;
  const std::int64_t nx = g.nx, ny = g.ny, cells = padded_cells(width);
  auto load = [&](std::int64_t j, GridRow& r) {
    wind_grid::load_row<Gusty>(law, g, i0, width, j, x, v, r);
  };
  GridRow rows[2];
  CellRow cell_rows[2];
  std::uint64_t pushed = 0;
  CellRow* below = &cell_rows[0];
  CellRow* above = &cell_rows[1];
  GridRow* here = &rows[0];
  GridRow* next = &rows[1];
  // The cells below row j0 (row j0 - 1 of cells): the strip below's, recomputed, not counted.
  if (j0 > 0) {
    load(j0 - 1, *next);
    load(j0, *here);
    cell_row<Gusty>(law, *next, *here, cells, *below);
  } else {
    wind_grid::zero_cells(*below);
    load(j0, *here);
  }
  for (std::int64_t j = j0; j < j1; ++j) {
    if (j + 1 < ny) {
      load(j + 1, *next);
      pushed += cell_row<Gusty>(law, *here, *next, cells, *above);
    } else {
      wind_grid::zero_cells(*above);
    }
    wind_grid::add_row(*below, *above, width, f + g.first + j * nx + i0);
    std::swap(below, above);
    std::swap(here, next);
  }
  return pushed;
}

template <bool Gusty>
std::uint64_t wind_grids(const WindLaw& law, const Model& m, State& s, int threads) {
  const Vec3* x = s.x().data();
  const Vec3* v = s.v().data();
  Vec3* f = s.f().data();
  std::uint64_t pushed = 0;
  for (const FaceGrid& g : m.surface.grids) {
    // Strips of rows, one per thread (the results do not depend on the split).
    const std::int64_t tiles = (std::int64_t(g.nx) + grid_tile - 1) / grid_tile;
    const std::int64_t strips = std::min<std::int64_t>(std::max(threads, 1), g.ny);
    const std::int64_t items = tiles * strips;
#pragma omp for schedule(static)
    for (std::int64_t item = 0; item < items; ++item) {
      const std::int64_t tile = item % tiles, strip = item / tiles;
      const std::int64_t i0 = tile * grid_tile;
      const std::int64_t width = std::min<std::int64_t>(grid_tile, g.nx - i0);
      const std::int64_t j0 = g.ny * strip / strips, j1 = g.ny * (strip + 1) / strips;
      pushed += wind_grid_tile<Gusty>(law, g, i0, width, j0, j1, x, v, f);
    }
  }
  return pushed;
}

template <bool Gusty>
std::uint64_t wind_loose(const WindLaw& law, const Model& m, State& s) {
  constexpr Real third = Real(1) / Real(3);
  const auto* tris = m.surface.triangles.data();
  const std::uint32_t* loose = m.surface.loose.data();
  const auto& groups = m.surface.loose_offsets;
  const Vec3* x = s.x().data();
  const Vec3* v = s.v().data();
  Vec3* f = s.f().data();
  std::uint64_t pushed = 0;
  for (std::size_t g = 0; g + 1 < groups.size(); ++g) {
    const auto begin = static_cast<std::int64_t>(groups[g]);
    const auto end = static_cast<std::int64_t>(groups[g + 1]);
    const std::int64_t blocks = (end - begin + wind_block - 1) / wind_block;
#pragma omp for schedule(static)
    for (std::int64_t blk = 0; blk < blocks; ++blk) {
      const std::int64_t first = begin + blk * wind_block;
      const std::int64_t count = std::min(wind_block, end - first);
      // [count] each: area vector 2 A n (m^2), centre (m), mean of the corners' velocities
      // (m/s), then the force on each corner (N).
      alignas(64) Real ax[wind_block], ay[wind_block], az[wind_block];
      alignas(64) Real px[wind_block], py[wind_block], pz[wind_block];
      alignas(64) Real vx[wind_block], vy[wind_block], vz[wind_block];
      alignas(64) Real fx[wind_block], fy[wind_block], fz[wind_block];
      GustBuffers gb;

      // Kept scalar on purpose: GCC would use AVX-512 gathers here, measured slower.
#pragma omp simd simdlen(1)
      for (std::int64_t j = 0; j < count; ++j) {
        const auto [a, b, c] = tris[loose[first + j]];
        const Vec3 area2 = cross(x[b] - x[a], x[c] - x[a]);
        const Vec3 centre = (x[a] + x[b] + x[c]) * third, vc = (v[a] + v[b] + v[c]) * third;
        ax[j] = area2.x, ay[j] = area2.y, az[j] = area2.z;
        px[j] = centre.x, py[j] = centre.y, pz[j] = centre.z;
        vx[j] = vc.x, vy[j] = vc.y, vz[j] = vc.z;
        pushed += norm2(area2) != 0;
      }
      if (Gusty) {
        gust_arguments(law.basis, px, py, pz, count, gb);
        wind_grid::gust_sines(law.basis, count, gb);
      }
      for (std::int64_t j = 0; j < count; ++j) {
        const Vec3 fc = gust::face_force(air<Gusty>(law.basis, gb, j), law.coef,
                                         Vec3{ax[j], ay[j], az[j]}, Vec3{vx[j], vy[j], vz[j]});
        fx[j] = fc.x, fy[j] = fc.y, fz[j] = fc.z;
      }

      for (std::int64_t j = 0; j < count; ++j) {
        const auto [a, b, c] = tris[loose[first + j]];
        const Vec3 fc{fx[j], fy[j], fz[j]};
        f[a] += fc;
        f[b] += fc;
        f[c] += fc;
      }
    }
  }
  return pushed;
}

template <bool Gusty>
std::uint64_t wind(const Model& m, State& s, int threads) {
  const WindLaw law = wind_grid::law(m.fields.wind, s.time);
  return wind_grids<Gusty>(law, m, s, threads) + wind_loose<Gusty>(law, m, s);
}

std::uint64_t wind(const Model& m, State& s, int threads) {
  return gust::basis(m.fields.wind, s.time).steady ? wind<false>(m, s, threads)
                                                   : wind<true>(m, s, threads);
}

}  // namespace

std::uint64_t field_forces(const Model& m, State& s, int threads) {
  const bool with_wind = m.fields.wind.active() && !m.surface.triangles.empty();
  std::uint64_t pushed = 0;
  if (threads > 1) {
#pragma omp parallel num_threads(threads)
    {
      point_fields(m, s);
      if (with_wind) {
        const std::uint64_t mine = wind(m, s, threads);
#pragma omp atomic
        pushed += mine;
      }
    }
  } else {
    point_fields(m, s);
    if (with_wind) pushed = wind(m, s, 1);
  }
  return pushed;
}

}  // namespace maille::stages