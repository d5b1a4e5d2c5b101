// Every built-in link kind's Jacobian blocks against central finite differences of its force.
#include <gtest/gtest.h>

#include <cmath>

#include "maille/links/conditional.hpp"
#include "maille/links/damper.hpp"
#include "maille/links/spring.hpp"
#include "maille/links/spring_damper.hpp"

namespace maille {
namespace {

double frobenius(const Mat3& a) {
  double s = 0;
  for (const auto& row : a.m)
    for (Real e : row) s += double(e) * e;
  return std::sqrt(s);
}

// Central differences with step 1e-6 m (or m/s): truncation error ~1e-12 relative, rounding
// ~1e-10 relative for forces of order 10 N: 1e-5 relative is the bound and has margin.
template <class K>
void expect_jacobian_matches(const typename K::Params& p) {
  const Vec3 xa{0.1, -0.2, 0.05}, xb{0.6, 0.15, -0.2}, va{0.3, -1, 0.5}, vb{-0.7, 0.4, 1.1};
  const LinkJacobian j = K::jacobian(xa, xb, va, vb, p, JacobianMode::exact);
  const Real eps = 1e-6;
  Mat3 dx, dv;
  for (int c = 0; c < 3; ++c) {
    Vec3 e{};
    (c == 0 ? e.x : c == 1 ? e.y : e.z) = eps;
    const Vec3 fx = (K::force(xa, xb + e, va, vb, p) - K::force(xa, xb - e, va, vb, p)) / (2 * eps);
    const Vec3 fv = (K::force(xa, xb, va, vb + e, p) - K::force(xa, xb, va, vb - e, p)) / (2 * eps);
    for (int r = 0; r < 3; ++r) {
      dx.m[r][c] = fx[r];
      dv.m[r][c] = fv[r];
    }
  }
  const double scale_x = std::max(frobenius(dx), 1e-12), scale_v = std::max(frobenius(dv), 1e-12);
  EXPECT_LT(frobenius(j.dx - dx) / scale_x, 1e-5) << K::keyword << " d/dx";
  if (frobenius(dv) > 0) {
    EXPECT_LT(frobenius(j.dv - dv) / scale_v, 1e-5) << K::keyword << " d/dv";
  }
  // The force on a depends on x_b - x_a only: d/dx_a is the opposite of d/dx_b.
  const Vec3 e{eps, 0, 0};
  const Vec3 fa = (K::force(xa + e, xb, va, vb, p) - K::force(xa - e, xb, va, vb, p)) / (2 * eps);
  for (int r = 0; r < 3; ++r) EXPECT_NEAR(fa[r], -j.dx.m[r][0], 1e-5 * scale_x) << K::keyword;
}

TEST(Jacobians, SpringStretchedAndCompressed) {
  expect_jacobian_matches<Spring>({300, 0.4});  // stretched (|d| ~ 0.63)
  expect_jacobian_matches<Spring>({300, 1.2});  // compressed
}

TEST(Jacobians, Damper) {
  expect_jacobian_matches<Damper>({7});
}

TEST(Jacobians, SpringDamper) {
  expect_jacobian_matches<SpringDamper>({300, 0.5, 7});
}

TEST(Jacobians, ConditionalActiveAndSilent) {
  expect_jacobian_matches<ConditionalSpringDamper>({300, 7, 1.0, 1.0});  // active: |d| < 1
  const auto silent = ConditionalSpringDamper::jacobian({0, 0, 0}, {2, 0, 0}, {}, {1, 0, 0},
                                                        {300, 7, 1.0, 1.0}, JacobianMode::exact);
  EXPECT_EQ(frobenius(silent.dx) + frobenius(silent.dv), 0);
}

// Definite mode gives symmetric, positive semi-definite blocks: a link adds
// (u_b - u_a)^T (h dv + h^2 dx) (u_b - u_a) to u^T A u, so A = M - h df/dv - h^2 df/dx stays SPD.
TEST(Jacobians, DefiniteModeIsSymmetricNegativeSemiDefinite) {
  const Vec3 xa{0, 0, 0}, xb{0.3, 0.1, 0}, va{}, vb{1, 2, 3};
  for (const LinkJacobian& j :
       {SpringDamper::jacobian(xa, xb, va, vb, {300, 1.0, 7}, JacobianMode::definite),
        SpringDamper::jacobian(xa, xb, va, vb, {300, 0.1, 7}, JacobianMode::definite)}) {
    for (const Mat3& a : {j.dx, j.dv}) {
      for (int r = 0; r < 3; ++r)
        for (int c = 0; c < 3; ++c) EXPECT_NEAR(a.m[r][c], a.m[c][r], 1e-12);
      for (const Vec3& u : {Vec3{1, 0, 0}, Vec3{0.3, -1, 0.2}, Vec3{0, 0, 1}})
        EXPECT_GE(dot(u, a * u), -1e-12);
    }
  }
}

}  // namespace
}  // namespace maille
