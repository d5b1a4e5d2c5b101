// Internal: the lanes kernels of vertex block descent (vbd_lanes.hpp), written once for W lanes
// with GCC vector extensions and compiled once per width in its own translation unit
// (vbd_lanes_w2.cpp, _w4.cpp with -mavx2, _w8.cpp with -mavx512f). Everything here lives in an
// anonymous namespace and calls no inline function of another header: a function compiled
// with AVX2 must never be the copy the linker keeps for the rest of the program.
//
// Bit identity with the scalar sweep (implicit_vbd.cpp, LinkPool::axial_point_terms,
// SpringDamper::axial, inverse_spd): every lane performs the scalar code's operations in the
// scalar code's order, one IEEE operation for one (the build has -ffp-contract=off: no fused
// multiply-add, and sqrt and division are correctly rounded at every width).
//
// Included once per translation unit, except by a per-target compilation (Highway's
// foreach_target.h in bench/bench_vbd_dispatch_hwy.cpp, the measurement of Highway's dynamic
// dispatch against vbd_lanes.cpp's table), which includes it once per target with
// MAILLE_VBD_LANES_NAMESPACE naming that target's namespace.
#if !defined(MAILLE_VBD_LANES_KERNEL_HPP) || defined(MAILLE_VBD_LANES_NAMESPACE)
#define MAILLE_VBD_LANES_KERNEL_HPP

#include <cstdint>
#include <type_traits>

#if defined(__AVX__) || defined(__SSE2__)
#include <immintrin.h>
#endif

#include "vbd_lanes_data.hpp"

namespace maille::vbd_lanes {
#if defined(MAILLE_VBD_LANES_NAMESPACE)
namespace MAILLE_VBD_LANES_NAMESPACE {
#else
namespace {
#endif

template <int W>
struct Lanes {
  // typedef, not using: GCC 12 drops the attribute of a dependent alias-declaration.
  typedef Real V __attribute__((vector_size(sizeof(Real) * W)));
  using Int = std::conditional_t<sizeof(Real) == 8, std::int64_t, std::int32_t>;
  typedef Int Mask __attribute__((vector_size(sizeof(Real) * W)));  // all ones (true) or zeros
};

template <int W>
inline typename Lanes<W>::V splat(Real s) {
  typename Lanes<W>::V v;
  for (int l = 0; l < W; ++l) v[l] = s;
  return v;
}

// Square root lane by lane: the instruction of the width where there is one.
template <int W>
inline typename Lanes<W>::V sqrt_lanes(typename Lanes<W>::V a) {
  if constexpr (sizeof(Real) == 8 && W == 8) {
#if defined(__AVX512F__)
    return (typename Lanes<W>::V)_mm512_sqrt_pd((__m512d)a);
#endif
  } else if constexpr (sizeof(Real) == 8 && W == 4) {
#if defined(__AVX__)
    return (typename Lanes<W>::V)_mm256_sqrt_pd((__m256d)a);
#endif
  } else if constexpr (sizeof(Real) == 8 && W == 2) {
#if defined(__SSE2__)
    return (typename Lanes<W>::V)_mm_sqrt_pd((__m128d)a);
#endif
  }
  typename Lanes<W>::V r;
  for (int l = 0; l < W; ++l) r[l] = __builtin_sqrt(a[l]);
  return r;
}

// x[3 j + c] of each lane's point j (positions and velocities are arrays of Vec3).
template <int W>
inline void gather3(const Real* a, const std::uint32_t* idx, typename Lanes<W>::V& x,
                    typename Lanes<W>::V& y, typename Lanes<W>::V& z) {
  for (int l = 0; l < W; ++l) {
    const Real* p = a + 3 * std::size_t(idx[l]);
    x[l] = p[0];
    y[l] = p[1];
    z[l] = p[2];
  }
}

template <int W>
inline typename Lanes<W>::Mask lane_mask(std::uint32_t bits) {
  typename Lanes<W>::Mask m;
  for (int l = 0; l < W; ++l) m[l] = (bits >> l) & 1u ? -1 : 0;
  return m;
}

// g and H (inertia, drag, and the lane pools' spring-dampers) of one block of W points,
// written to g (Vec3 per point) and h (Mat3 per point) for its `lanes` real points.
template <int W>
void block_terms(const Block& b, const Rows& rows, const Step& s, Real* g, Real* h) {
  using V = typename Lanes<W>::V;
  const std::uint32_t* pts = b.points;
  V xi, yi, zi, vxi, vyi, vzi, gx, gy, gz, mass;
  gather3<W>(s.x, pts, xi, yi, zi);
  gather3<W>(s.v, pts, vxi, vyi, vzi);
  for (int l = 0; l < W; ++l) mass[l] = s.mass[pts[l]];
  {
    // g = (y - x) (m / h^2) - v (drag m)
    V yx, yy, yz;
    gather3<W>(s.y, pts, yx, yy, yz);
    const V a = mass * splat<W>(s.inv_h2), c = splat<W>(s.drag) * mass;
    gx = (yx - xi) * a - vxi * c;
    gy = (yy - yi) * a - vyi * c;
    gz = (yz - zi) * a - vzi * c;
  }
  // H = I m (1/h^2 + drag/h): the identity's ones and zeros times the factor.
  const V inertia = mass * splat<W>(s.inv_h2 + s.drag * s.inv_h);
  const V zero = splat<W>(0) * inertia;
  V h00 = splat<W>(1) * inertia, h11 = h00, h22 = h00, h01 = zero, h02 = zero, h12 = zero;
  const V tiny = splat<W>(Real(1e-30)), one = splat<W>(1), nil = splat<W>(0);
  const V inv_h = splat<W>(s.inv_h);
  std::uint32_t row = b.first_row;
  for (std::uint32_t q = 0; q < b.pools; ++q) {
    V fx = nil, fy = nil, fz = nil;
    V a00 = nil, a11 = nil, a22 = nil, a01 = nil, a02 = nil, a12 = nil;
    for (const std::uint32_t end = row + b.depth[q]; row < end; ++row) {
      const std::uint32_t* nbr = rows.neighbour + std::size_t(row) * W;
      const Real* par = rows.params + std::size_t(row) * 3 * W;
      V k, rest, z;
      for (int l = 0; l < W; ++l) {
        k[l] = par[l];
        rest[l] = par[W + l];
        z[l] = par[2 * W + l];
      }
      V xj, yj, zj, vxj, vyj, vzj;
      gather3<W>(s.x, nbr, xj, yj, zj);
      gather3<W>(s.v, nbr, vxj, vyj, vzj);
      const V dx = xj - xi, dy = yj - yi, dz = zj - zi;
      const V d2 = dx * dx + dy * dy + dz * dz;
      const V dvd = (vxj - vxi) * dx + (vyj - vyi) * dy + (vzj - vzi) * dz;
      // SpringDamper::axial, operation for operation.
      const V inv = one / (sqrt_lanes<W>(d2) + tiny);
      const V stretch = one - rest * inv;
      const V t = stretch > nil ? stretch : nil;
      const V force = k * stretch + z * dvd * inv * inv;
      const V iso = k * t;
      const V axial = (k * (one - t) + z * inv_h) * (inv * inv);
      fx += dx * force;
      fy += dy * force;
      fz += dz * force;
      // axial_block: (d d^T) axial, plus iso on the diagonal.
      a00 += dx * dx * axial + iso;
      a11 += dy * dy * axial + iso;
      a22 += dz * dz * axial + iso;
      a01 += dx * dy * axial;
      a02 += dx * dz * axial;
      a12 += dy * dz * axial;
    }
    // A point with no link in this pool gets nothing added (the scalar pool commits nothing).
    const typename Lanes<W>::Mask has = lane_mask<W>(b.has[q]);
    gx = has ? gx + fx : gx;
    gy = has ? gy + fy : gy;
    gz = has ? gz + fz : gz;
    h00 = has ? h00 + a00 : h00;
    h11 = has ? h11 + a11 : h11;
    h22 = has ? h22 + a22 : h22;
    h01 = has ? h01 + a01 : h01;
    h02 = has ? h02 + a02 : h02;
    h12 = has ? h12 + a12 : h12;
  }
  for (std::uint32_t l = 0; l < b.lanes; ++l) {
    Real* gi = g + 3 * std::size_t(pts[l]);
    gi[0] = gx[l];
    gi[1] = gy[l];
    gi[2] = gz[l];
    Real* hi = h + 9 * std::size_t(pts[l]);  // symmetric to the bit: d_r d_c = d_c d_r
    hi[0] = h00[l];
    hi[1] = h01[l];
    hi[2] = h02[l];
    hi[3] = h01[l];
    hi[4] = h11[l];
    hi[5] = h12[l];
    hi[6] = h02[l];
    hi[7] = h12[l];
    hi[8] = h22[l];
  }
}

// The Newton steps dx = H^-1 g of one block's points (inverse_spd, operation for operation),
// from g and h as the scalar terms left them; dx[3 l + c] for lane l.
template <int W>
void block_solve(const std::uint32_t* pts, std::uint32_t lanes, const Real* g, const Real* h,
                 Real* out) {
  using V = typename Lanes<W>::V;
  V m[9], gx, gy, gz;
  for (int l = 0; l < W; ++l) {
    const Real* hi = h + 9 * std::size_t(pts[l]);
    for (int e = 0; e < 9; ++e) m[e][l] = hi[e];
  }
  gather3<W>(g, pts, gx, gy, gz);
  const V c00 = m[4] * m[8] - m[5] * m[7];
  const V c01 = m[5] * m[6] - m[3] * m[8];
  const V c02 = m[3] * m[7] - m[4] * m[6];
  const V det = m[0] * c00 + m[1] * c01 + m[2] * c02;
  const V one = splat<W>(1), nil = splat<W>(0);
  const V inv_det = one / det;
  // !(|det| > 0): the identity (a zero or non-finite determinant).
  const auto singular = !((det > nil) | (det < nil));
  auto entry = [&](V adj, Real identity) { return singular ? splat<W>(identity) : adj * inv_det; };
  const V r00 = entry(c00, 1);
  const V r01 = entry(m[2] * m[7] - m[1] * m[8], 0);
  const V r02 = entry(m[1] * m[5] - m[2] * m[4], 0);
  const V r10 = entry(c01, 0);
  const V r11 = entry(m[0] * m[8] - m[2] * m[6], 1);
  const V r12 = entry(m[2] * m[3] - m[0] * m[5], 0);
  const V r20 = entry(c02, 0);
  const V r21 = entry(m[1] * m[6] - m[0] * m[7], 0);
  const V r22 = entry(m[0] * m[4] - m[1] * m[3], 1);
  const V dx = r00 * gx + r01 * gy + r02 * gz;
  const V dy = r10 * gx + r11 * gy + r12 * gz;
  const V dz = r20 * gx + r21 * gy + r22 * gz;
  for (std::uint32_t l = 0; l < lanes; ++l) {
    out[3 * l] = dx[l];
    out[3 * l + 1] = dy[l];
    out[3 * l + 2] = dz[l];
  }
}

}  // namespace
}  // namespace maille::vbd_lanes

// Defines the kernels of one width: included last by vbd_lanes_wN.cpp.
#define MAILLE_VBD_LANES_KERNELS(W)                                  \
  namespace maille::vbd_lanes {                                      \
  extern const Kernels kKernels##W;                                  \
  const Kernels kKernels##W = {W, &block_terms<W>, &block_solve<W>}; \
  }

#endif  // MAILLE_VBD_LANES_KERNEL_HPP
