#include <algorithm>
#include <cmath>
#include <cstdint>
#include <utility>

#include "gust.hpp"
#include "point_update.hpp"
#include "stages.hpp"

// Tells the vectoriser that iterations of the next loop do not overlap in memory (the wind
// loops write F0 at [k] and F1 at [cells + k] of one buffer: GCC versioned them on a run-time
// overlap test, and the scalar version ran).
#if defined(__clang__)
#define MAILLE_NO_OVERLAP _Pragma("clang loop vectorize(assume_safety)")
#elif defined(__GNUC__)
#define MAILLE_NO_OVERLAP _Pragma("GCC ivdep")
#else
#define MAILLE_NO_OVERLAP
#endif

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
// row. Per tile, a row of points is copied into struct-of-arrays buffers on the stack (with each
// point's coordinates along and across the wind when there are gusts), the row of cells between
// it and the next is computed by vectorised loops with contiguous loads only (the gust's
// arguments of both faces of each cell, double; the sines, float; geometry and force of both
// faces, double, into a buffer), and each point of the row sums the forces of its six faces
// from that row of cells and the one below:
//
//      row j+1   d ----- c            point (i, j) is corner of: F0, F1 of cell (i, j),
//                |  F1 / |            F0 of cell (i-1, j), F0 and F1 of cell (i-1, j-1),
//                |   /   |            F1 of cell (i, j-1); cells outside the grid count 0.
//                | / F0  |
//      row j     a ----- b            F0 = (a, b, c), F1 = (a, c, d)
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
constexpr std::int64_t grid_tile = 64;
constexpr std::int64_t wind_block = 64;

struct WindLaw {
  gust::Basis basis;
  Real coef = 0;  // rho C_d / 12 (gust::face_force)
};

// A tile of width points runs the cells i0 - 1 .. i0 + width - 1 (k = i - i0 + 1), padded to a
// multiple of 4 cells so that the vectorised loops have no scalar remainder.
constexpr std::int64_t padded_cells(std::int64_t width) {
  return (width + 1 + 3) / 4 * 4;
}
constexpr std::int64_t cell_cap = padded_cells(grid_tile);

// One row of a tile: points i0 - 1 .. i0 - 1 + cells (index k = i - i0 + 1), x and v by axis.
// Where the grid has no such point (left of its first column, right of its last, the padding),
// the row repeats its neighbour: the cell there is then degenerate (a2 = 0 exactly) and gets
// no force, so every row of a tile runs the same cells with no test.
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
constexpr std::int64_t face_cap = 2 * cell_cap;
struct CellRow {
  alignas(64) Real f[3][face_cap];
};
// The gust at the faces of one row of cells (indexed as CellRow) or of a block of loose faces.
struct GustBuffers {
  alignas(64) float r[4][face_cap];     // the four reduced arguments, turns
  alignas(64) float gust[3][face_cap];  // w - U at the centre, m/s
};
static_assert(face_cap >= wind_block);

void load_row(const Vec3* x, const Vec3* v, std::int64_t base, std::int64_t k0, std::int64_t k1,
              GridRow& r) {
  constexpr Real third = Real(1) / Real(3);
  for (std::int64_t k = k0; k < k1; ++k) {
    const Vec3 p = x[base + k], u = v[base + k];
    r.x[0][k] = p.x, r.x[1][k] = p.y, r.x[2][k] = p.z;
    r.v[0][k] = u.x * third, r.v[1][k] = u.y * third, r.v[2][k] = u.z * third;
  }
}

// The gust at faces [0, n) from their reduced arguments (gb.r) into gb.gust: float only.
void gust_sines(const gust::Basis& basis, std::int64_t n, GustBuffers& gb) {
  const float* __restrict r0 = gb.r[0];
  const float* __restrict r1 = gb.r[1];
  const float* __restrict r2 = gb.r[2];
  const float* __restrict r3 = gb.r[3];
  float* __restrict gx = gb.gust[0];
  float* __restrict gy = gb.gust[1];
  float* __restrict gz = gb.gust[2];
  MAILLE_NO_OVERLAP
  for (std::int64_t j = 0; j < n; ++j) {
    const float r[4] = {r0[j], r1[j], r2[j], r3[j]};
    float g[3];
    gust::gust_from(basis, r, g);
    gx[j] = g[0], gy[j] = g[1], gz[j] = g[2];
  }
}

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

// The cells k in [0, cells) between rows lo and hi into out; returns how many faces of the
// cells k >= 1 are not degenerate (cell 0 is the left neighbour tile's or a ghost).
template <bool Gusty>
std::uint64_t cell_row(const WindLaw& law, const GridRow* __restrict lo,
                       const GridRow* __restrict hi, std::int64_t cells, CellRow* __restrict out) {
  GustBuffers gb;
  if (Gusty) {
    // Arguments of F0 then F1, from the corners' s and q (double to float), then the sines.
    // Separate loops of one width each: fused with the force, GCC 12 vectorised none of it.
    float* __restrict r0 = gb.r[0];
    float* __restrict r1 = gb.r[1];
    float* __restrict r2 = gb.r[2];
    float* __restrict r3 = gb.r[3];
    float* __restrict t0 = gb.r[0] + cells;
    float* __restrict t1 = gb.r[1] + cells;
    float* __restrict t2 = gb.r[2] + cells;
    float* __restrict t3 = gb.r[3] + cells;
    const double* __restrict ls = lo->s;
    const double* __restrict lq = lo->q;
    const double* __restrict hs = hi->s;
    const double* __restrict hq = hi->q;
    MAILLE_NO_OVERLAP
    for (std::int64_t k = 0; k < cells; ++k) {
      const double s_ac = ls[k] + hs[k + 1], q_ac = lq[k] + hq[k + 1];
      float r[4];
      gust::arguments(law.basis, s_ac + ls[k + 1], q_ac + lq[k + 1], r);
      r0[k] = r[0], r1[k] = r[1], r2[k] = r[2], r3[k] = r[3];
      gust::arguments(law.basis, s_ac + hs[k], q_ac + hq[k], r);
      t0[k] = r[0], t1[k] = r[1], t2[k] = r[2], t3[k] = r[3];
    }
    gust_sines(law.basis, 2 * cells, gb);
  }
  const Real* __restrict lx = lo->x[0];
  const Real* __restrict ly = lo->x[1];
  const Real* __restrict lz = lo->x[2];
  const Real* __restrict hx = hi->x[0];
  const Real* __restrict hy = hi->x[1];
  const Real* __restrict hz = hi->x[2];
  const Real* __restrict lvx = lo->v[0];
  const Real* __restrict lvy = lo->v[1];
  const Real* __restrict lvz = lo->v[2];
  const Real* __restrict hvx = hi->v[0];
  const Real* __restrict hvy = hi->v[1];
  const Real* __restrict hvz = hi->v[2];
  Real* __restrict f0x = out->f[0];
  Real* __restrict f0y = out->f[1];
  Real* __restrict f0z = out->f[2];
  Real* __restrict f1x = out->f[0] + cells;
  Real* __restrict f1y = out->f[1] + cells;
  Real* __restrict f1z = out->f[2] + cells;
  // The pressure law in float, like the gust: a face's force to about 1e-7 of the largest one
  // (1.5e-7 measured by physics.WindStage), far below what the drag law knows, at twice the
  // vector width. Edges and velocity sums are differences and
  // sums of doubles taken in double first (positions are metres from the origin), then rounded.
  const float coef = float(law.coef);
  const float mx = float(law.basis.mean.x), my = float(law.basis.mean.y),
              mz = float(law.basis.mean.z);
  const float* __restrict g0x = gb.gust[0];
  const float* __restrict g0y = gb.gust[1];
  const float* __restrict g0z = gb.gust[2];
  std::uint64_t pushed = 0;
  MAILLE_NO_OVERLAP
  for (std::int64_t k = 0; k < cells; ++k) {
    // Cell corners a = lo[k], b = lo[k + 1], c = hi[k + 1], d = hi[k]; faces abc and acd.
    const float abx = float(lx[k + 1] - lx[k]), aby = float(ly[k + 1] - ly[k]),
                abz = float(lz[k + 1] - lz[k]);
    const float acx = float(hx[k + 1] - lx[k]), acy = float(hy[k + 1] - ly[k]),
                acz = float(hz[k + 1] - lz[k]);
    const float adx = float(hx[k] - lx[k]), ady = float(hy[k] - ly[k]), adz = float(hz[k] - lz[k]);
    const float n0x = aby * acz - abz * acy, n0y = abz * acx - abx * acz,
                n0z = abx * acy - aby * acx;
    const float n1x = acy * adz - acz * ady, n1y = acz * adx - acx * adz,
                n1z = acx * ady - acy * adx;
    const double vacx = lvx[k] + hvx[k + 1], vacy = lvy[k] + hvy[k + 1], vacz = lvz[k] + hvz[k + 1];
    const float s0x = float(vacx + lvx[k + 1]), s0y = float(vacy + lvy[k + 1]),
                s0z = float(vacz + lvz[k + 1]);
    const float s1x = float(vacx + hvx[k]), s1y = float(vacy + hvy[k]), s1z = float(vacz + hvz[k]);
    const float w0x = Gusty ? mx + g0x[k] : mx, w0y = Gusty ? my + g0y[k] : my,
                w0z = Gusty ? mz + g0z[k] : mz;
    const float w1x = Gusty ? mx + g0x[cells + k] : mx, w1y = Gusty ? my + g0y[cells + k] : my,
                w1z = Gusty ? mz + g0z[cells + k] : mz;
    // gust::face_force by component, in float: coef |d| d / |a2|^2 a2, d = (w - v) . a2.
    const float d0 = (w0x - s0x) * n0x + (w0y - s0y) * n0y + (w0z - s0z) * n0z;
    const float d1 = (w1x - s1x) * n1x + (w1y - s1y) * n1y + (w1z - s1z) * n1z;
    const float l0 = n0x * n0x + n0y * n0y + n0z * n0z;
    const float l1 = n1x * n1x + n1y * n1y + n1z * n1z;
    const float c0 = gust::face_force_scale(coef, d0, l0);
    const float c1 = gust::face_force_scale(coef, d1, l1);
    f0x[k] = Real(n0x * c0), f0y[k] = Real(n0y * c0), f0z[k] = Real(n0z * c0);
    f1x[k] = Real(n1x * c1), f1y[k] = Real(n1y * c1), f1z[k] = Real(n1z * c1);
    pushed += std::uint64_t(l0 != 0) + std::uint64_t(l1 != 0);
  }
  // Cell 0 is not this tile's to count.
  const Vec3 a{lx[0], ly[0], lz[0]}, b{lx[1], ly[1], lz[1]}, c{hx[1], hy[1], hz[1]},
      d{hx[0], hy[0], hz[0]};
  pushed -= std::uint64_t(norm2(cross(b - a, c - a)) != 0) +
            std::uint64_t(norm2(cross(c - a, d - a)) != 0);
  return pushed;
}

void zero_cells(CellRow& r) {
  for (int axis = 0; axis < 3; ++axis)
    for (std::int64_t k = 0; k < face_cap; ++k) r.f[axis][k] = 0;
}

// Points i0 .. i0 + width - 1 of one row: f += the forces of their six faces.
void add_row(const CellRow& below, const CellRow& above, std::int64_t width, Vec3* f) {
  const std::int64_t cells = padded_cells(width);
  Real sum[3][grid_tile];
  for (int axis = 0; axis < 3; ++axis) {
    const Real* a0 = above.f[axis];
    const Real* a1 = above.f[axis] + cells;
    const Real* b0 = below.f[axis];
    const Real* b1 = below.f[axis] + cells;
    for (std::int64_t i = 0; i < width; ++i)
      sum[axis][i] = ((a0[i + 1] + a1[i + 1]) + a0[i]) + ((b0[i] + b1[i]) + b1[i + 1]);
  }
  for (std::int64_t i = 0; i < width; ++i) f[i] += Vec3{sum[0][i], sum[1][i], sum[2][i]};
}

// Tile [i0, i0 + width) x rows [j0, j1) of grid g.
template <bool Gusty>
std::uint64_t wind_grid_tile(const WindLaw& law, const FaceGrid& g, std::int64_t i0,
                             std::int64_t width, std::int64_t j0, std::int64_t j1, const Vec3* x,
                             const Vec3* v, Vec3* f) {
  const std::int64_t nx = g.nx, ny = g.ny, cells = padded_cells(width);
  // Points k in [p0, p1) of a row exist; the others, up to k = cells, are ghosts.
  const std::int64_t p0 = i0 == 0 ? 1 : 0;
  const std::int64_t p1 = i0 + width == nx ? width + 1 : width + 2;
  auto load = [&](std::int64_t j, GridRow& r) {
    load_row(x, v, std::int64_t(g.first) + j * nx + i0 - 1, p0, p1, r);
    for (int axis = 0; axis < 3; ++axis) {
      if (p0 == 1) r.x[axis][0] = r.x[axis][1], r.v[axis][0] = r.v[axis][1];
      for (std::int64_t k = p1; k <= cells; ++k)
        r.x[axis][k] = r.x[axis][p1 - 1], r.v[axis][k] = r.v[axis][p1 - 1];
    }
    if (Gusty) {
      constexpr Real third = Real(1) / Real(3);
      const Vec3 ka = law.basis.k_along * third, kc = law.basis.k_across * third;
      for (std::int64_t k = 0; k <= cells; ++k) {
        const Vec3 p{r.x[0][k], r.x[1][k], r.x[2][k]};
        r.s[k] = dot(ka, p), r.q[k] = dot(kc, p);
      }
    }
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
    cell_row<Gusty>(law, next, here, cells, below);
  } else {
    zero_cells(*below);
    load(j0, *here);
  }
  for (std::int64_t j = j0; j < j1; ++j) {
    if (j + 1 < ny) {
      load(j + 1, *next);
      pushed += cell_row<Gusty>(law, here, next, cells, above);
    } else {
      zero_cells(*above);
    }
    add_row(*below, *above, width, f + g.first + j * nx + i0);
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
        gust_sines(law.basis, count, gb);
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
  const WindField& w = m.fields.wind;
  const WindLaw law{gust::basis(w, s.time), w.density * w.drag_coefficient / Real(12)};
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
