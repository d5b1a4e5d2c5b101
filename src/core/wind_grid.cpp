#include "wind_grid.hpp"

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

namespace maille::wind_grid {

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

template <bool Gusty>
void load_row(const WindLaw& law, const FaceGrid& g, std::int64_t i0, std::int64_t width,
              std::int64_t j, const Vec3* x, const Vec3* v, GridRow& r) {
  constexpr Real third = Real(1) / Real(3);
  const std::int64_t nx = g.nx, cells = padded_cells(width);
  // Points k in [p0, p1) of the row exist; the others, up to k = cells, are ghosts.
  const std::int64_t p0 = i0 == 0 ? 1 : 0;
  const std::int64_t p1 = i0 + width == nx ? width + 1 : width + 2;
  const std::int64_t base = std::int64_t(g.first) + j * nx + i0 - 1;
  for (std::int64_t k = p0; k < p1; ++k) {
    const Vec3 p = x[base + k], u = v[base + k];
    r.x[0][k] = p.x, r.x[1][k] = p.y, r.x[2][k] = p.z;
    r.v[0][k] = u.x * third, r.v[1][k] = u.y * third, r.v[2][k] = u.z * third;
  }
  for (int axis = 0; axis < 3; ++axis) {
    if (p0 == 1) r.x[axis][0] = r.x[axis][1], r.v[axis][0] = r.v[axis][1];
    for (std::int64_t k = p1; k <= cells; ++k)
      r.x[axis][k] = r.x[axis][p1 - 1], r.v[axis][k] = r.v[axis][p1 - 1];
  }
  if (Gusty) {
    const Vec3 ka = law.basis.k_along * third, kc = law.basis.k_across * third;
    for (std::int64_t k = 0; k <= cells; ++k) {
      const Vec3 p{r.x[0][k], r.x[1][k], r.x[2][k]};
      r.s[k] = dot(ka, p), r.q[k] = dot(kc, p);
    }
  }
}

template <bool Gusty>
std::uint64_t cell_row(const WindLaw& law, const GridRow& lo_row, const GridRow& hi_row,
                       std::int64_t cells, CellRow& out_row) {
  const GridRow* __restrict lo = &lo_row;
  const GridRow* __restrict hi = &hi_row;
  CellRow* __restrict out = &out_row;
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
  // The rows by axis, read and written through the restrict pointers above: F0 at [k], F1 at
  // [cells + k].
  const auto& [lx, ly, lz] = lo->x;
  const auto& [hx, hy, hz] = hi->x;
  const auto& [lvx, lvy, lvz] = lo->v;
  const auto& [hvx, hvy, hvz] = hi->v;
  auto& [f0x, f0y, f0z] = out->f;
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

template void load_row<false>(const WindLaw&, const FaceGrid&, std::int64_t, std::int64_t,
                              std::int64_t, const Vec3*, const Vec3*, GridRow&);
template void load_row<true>(const WindLaw&, const FaceGrid&, std::int64_t, std::int64_t,
                             std::int64_t, const Vec3*, const Vec3*, GridRow&);
template std::uint64_t cell_row<false>(const WindLaw&, const GridRow&, const GridRow&, std::int64_t,
                                       CellRow&);
template std::uint64_t cell_row<true>(const WindLaw&, const GridRow&, const GridRow&, std::int64_t,
                                      CellRow&);

}  // namespace maille::wind_grid
