// Self-collision's shared contact laws (include/maille/detail/contact_laws.glsl) against their
// definitions: closest points against a dense search, forces against minus the energy's gradient
// and blocks against the forces' Jacobians, both by central finite differences.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <random>

#include "maille/mat3.hpp"
#include "maille/shared_laws.hpp"

namespace maille {
namespace {

using Stencil = std::array<Vec3, 4>;

Vec3 along(int axis, double h) {
  return {axis == 0 ? h : 0, axis == 1 ? h : 0, axis == 2 ? h : 0};
}

Vec3 random_point(std::mt19937& rng, double scale) {
  std::uniform_real_distribution<double> u(-scale, scale);
  return {u(rng), u(rng), u(rng)};
}

// The closest points' coefficients c (sum c_j x_j = d) of a point-triangle stencil or an edge
// pair, as the engine's terms take them.
std::array<Real, 4> coefficients(const Stencil& x, bool edges) {
  if (!edges) {
    const Vec3 w = law::triangle_closest_weights(x[0], x[1], x[2], x[3]);
    return {1, -w.x, -w.y, -w.z};
  }
  Real s = 0, t = 0;
  law::edge_edge_params(x[0], x[1], x[2], x[3], s, t);
  return {1 - s, s, -(1 - t), -t};
}
Vec3 gap(const Stencil& x, const std::array<Real, 4>& c) {
  return x[0] * c[0] + x[1] * c[1] + x[2] * c[2] + x[3] * c[3];
}
double energy(const Stencil& x, bool edges, Real k, Real s) {
  return law::contact_energy(norm(gap(x, coefficients(x, edges))), k, s);
}
// Stencil point j's force (c_j F).
Vec3 force(const Stencil& x, const Stencil& v, bool edges, int j, Real k, Real z, Real s) {
  const auto c = coefficients(x, edges);
  const Vec3 dv = gap(v, c);
  return law::stencil_contact_force(gap(x, c), dv, k, z, s) * c[std::size_t(j)];
}

TEST(ContactLaws, TriangleWeightsGiveTheClosestPointOfADenseSearch) {
  std::mt19937 rng(7);
  for (int trial = 0; trial < 200; ++trial) {
    const Vec3 p = random_point(rng, 1), a = random_point(rng, 1), b = random_point(rng, 1),
               c = random_point(rng, 1);
    const Vec3 w = law::triangle_closest_weights(p, a, b, c);
    EXPECT_NEAR(w.x + w.y + w.z, 1, 1e-12);
    EXPECT_GE(std::min({w.x, w.y, w.z}), -1e-12);
    const double found = norm(p - (a * w.x + b * w.y + c * w.z));
    double best = 1e300;  // a 200 x 200 barycentric grid: within 1 % of the sides
    for (int i = 0; i <= 200; ++i)
      for (int j = 0; i + j <= 200; ++j) {
        const double u = i / 200.0, v = j / 200.0;
        best = std::min(best, double(norm(p - (a * (1 - u - v) + b * u + c * v))));
      }
    EXPECT_LE(found, best + 1e-12) << trial;
    EXPECT_GE(found, best - 0.02) << trial;  // the grid's spacing bounds how far it can be off
  }
}

TEST(ContactLaws, EdgeParametersGiveTheClosestPointsOfADenseSearch) {
  std::mt19937 rng(11);
  for (int trial = 0; trial < 200; ++trial) {
    const Vec3 a0 = random_point(rng, 1), a1 = random_point(rng, 1), b0 = random_point(rng, 1),
               b1 = random_point(rng, 1);
    Real s = -1, t = -1;
    law::edge_edge_params(a0, a1, b0, b1, s, t);
    ASSERT_TRUE(s >= 0 && s <= 1 && t >= 0 && t <= 1);
    const double found = norm(a0 * (1 - s) + a1 * s - (b0 * (1 - t) + b1 * t));
    double best = 1e300;
    for (int i = 0; i <= 400; ++i)
      for (int j = 0; j <= 400; ++j) {
        const double u = i / 400.0, v = j / 400.0;
        best = std::min(best, double(norm(a0 * (1 - u) + a1 * u - (b0 * (1 - v) + b1 * v))));
      }
    EXPECT_LE(found, best + 1e-12) << trial;
    EXPECT_GE(found, best - 0.02) << trial;
  }
}

// Two parallel edges at distance 0.1, one 1 m long, the other over [0.25, 0.65] of it: the
// closest points found are at the right distance and one of them is a corner (the face contacts'
// share: the pair does not push twice), and as the second edge turns through parallel (1e-4 rad
// per step) the distance changes continuously.
TEST(ContactLaws, ParallelEdgesMeetAtACornerAndTurnContinuously) {
  const Vec3 a0{0, 0, 0}, a1{1, 0, 0};
  Real s = 0, t = 0;
  law::edge_edge_params(a0, a1, {0.25, 0.1, 0}, {0.65, 0.1, 0}, s, t);
  EXPECT_NEAR(norm(a0 * (1 - s) + a1 * s - (Vec3{0.25, 0.1, 0} * (1 - t) + Vec3{0.65, 0.1, 0} * t)),
              0.1, 1e-12);
  EXPECT_TRUE(s == 0 || s == 1 || t == 0 || t == 1);
  EXPECT_FALSE(law::edge_edge_acts(s, t, true, true, true, true));
  double last = -1;
  for (int k = -400; k <= 400; ++k) {
    const double angle = 1e-4 * k, c = std::cos(angle), sn = std::sin(angle);
    const Vec3 mid{0.45, 0.1, 0}, half{0.2 * c, 0, 0.2 * sn};
    const Vec3 b0 = mid - half, b1 = mid + half;
    law::edge_edge_params(a0, a1, b0, b1, s, t);
    const double d = norm(a0 * (1 - s) + a1 * s - (b0 * (1 - t) + b1 * t));
    if (last >= 0) {
      EXPECT_LT(std::abs(d - last), 1e-4) << k;  // |dd| <= 0.2 m x 1e-4 rad
    }
    last = d;
  }
}

// Central differences with step 1e-7 m on gaps of about 0.02 m: the truncation error is
// O(h^2 |E'''|) ~ 1e-14 k s and the rounding error ~ 1e-16 E / 1e-7, both far below the 1e-6
// relative tolerance.
TEST(ContactLaws, ForcesAreMinusTheEnergysGradient) {
  const Real k = 800, s = 0.03;
  const Stencil zero{};
  // A particle above a face, above an edge, above a corner; two crossing edges.
  const std::array<std::pair<Stencil, bool>, 4> cases{{
      {{Vec3{0.3, 0.012, 0.2}, Vec3{0, 0, 0}, Vec3{1, 0, 0}, Vec3{0, 0, 1}}, false},
      {{Vec3{0.5, 0.01, -0.004}, Vec3{0, 0, 0}, Vec3{1, 0, 0}, Vec3{0, 0, 1}}, false},
      {{Vec3{-0.01, 0.013, -0.006}, Vec3{0, 0, 0}, Vec3{1, 0, 0}, Vec3{0, 0, 1}}, false},
      {{Vec3{0, 0.015, 0.4}, Vec3{1, 0.002, 0.45}, Vec3{0.3, 0, 0}, Vec3{0.35, 0.001, 1}}, true},
  }};
  for (const auto& [x, edges] : cases) {
    ASSERT_GT(energy(x, edges, k, s), 0);
    for (int j = 0; j < 4; ++j) {
      const Vec3 f = force(x, zero, edges, j, k, 0, s);
      for (int axis = 0; axis < 3; ++axis) {
        const double h = 1e-7;
        Stencil plus = x, minus = x;
        plus[std::size_t(j)] += along(axis, h);
        minus[std::size_t(j)] -= along(axis, h);
        const double grad = (energy(plus, edges, k, s) - energy(minus, edges, k, s)) / (2 * h);
        EXPECT_NEAR(f[axis], -grad, 1e-6 * k * s + 1e-9)
            << (edges ? "edges" : "triangle") << " point " << j << " axis " << axis;
      }
    }
  }
}

// The block (k + z / h) n n^T per unit c_j^2 is the Gauss-Newton part of -dF_j/dx_j. For a
// particle over a face it is the whole Jacobian (sliding along the face leaves the gap and n
// unchanged). Elsewhere the rest is F times the derivatives of c_j and n: the weights and the
// normal turn by O(1/l) per metre a corner moves (l the stencil's shortest edge), so the rest is
// at most a few k (s - d) / l; the tolerance is 4 k (s - d) / l. The damper's part is -dF/dv
// exactly: z c_j^2 n n^T.
TEST(ContactLaws, BlocksAreTheForcesJacobians) {
  const Real k = 800, z = 3, s = 0.03, inv_h = 60;
  const Stencil zero{};
  const std::array<std::pair<Stencil, bool>, 2> cases{{
      {{Vec3{0.3, 0.012, 0.2}, Vec3{0, 0, 0}, Vec3{1, 0, 0}, Vec3{0, 0, 1}}, false},
      {{Vec3{0, 0.015, 0.4}, Vec3{1, 0.002, 0.45}, Vec3{0.3, 0, 0}, Vec3{0.35, 0.001, 1}}, true},
  }};
  for (const auto& [x, edges] : cases) {
    const auto c = coefficients(x, edges);
    const Vec3 d = gap(x, c);
    const Vec3 n = d / norm(d);
    const Mat3 block = law::stencil_contact_block(d, k, z, s, inv_h);
    const double shortest =
        edges ? std::min(norm(x[1] - x[0]), norm(x[3] - x[2]))
              : std::min({norm(x[2] - x[1]), norm(x[3] - x[2]), norm(x[1] - x[3])});
    const double rest = 4 * k * (s - norm(d)) / shortest;
    for (int j = 0; j < 4; ++j) {
      const double cj2 = double(c[std::size_t(j)] * c[std::size_t(j)]);
      Mat3 jx{}, jv{};  // -dF_j/dx_j and -dF_j/dv_j by central differences
      for (int axis = 0; axis < 3; ++axis) {
        const double h = 1e-7;
        Stencil xp = x, xm = x, vp = zero, vm = zero;
        xp[std::size_t(j)] += along(axis, h);
        xm[std::size_t(j)] -= along(axis, h);
        vp[std::size_t(j)] += along(axis, h);
        vm[std::size_t(j)] -= along(axis, h);
        const Vec3 dx = (force(xp, zero, edges, j, k, 0, s) - force(xm, zero, edges, j, k, 0, s)) *
                        (-1 / (2 * h));
        const Vec3 dvv =
            (force(x, vp, edges, j, k, z, s) - force(x, vm, edges, j, k, z, s)) * (-1 / (2 * h));
        for (int r = 0; r < 3; ++r) {
          jx.m[r][axis] = dx[r];
          jv.m[r][axis] = dvv[r];
        }
      }
      const bool exact = !edges && j == 0;
      const double tol = exact ? 1e-5 * k : rest;
      EXPECT_NEAR(dot(n, jx * n), k * cj2, tol) << "point " << j;
      EXPECT_NEAR(dot(n, block * n), (k + z * inv_h), 1e-9 * k);
      for (int r = 0; r < 3; ++r)
        for (int q = 0; q < 3; ++q) {
          EXPECT_NEAR(jv.m[r][q], z * cj2 * double(n[r] * n[q]), 1e-5 * z) << r << q;
          EXPECT_NEAR(jx.m[r][q], k * cj2 * double(n[r] * n[q]), tol) << j << r << q;
        }
    }
  }
}

TEST(ContactLaws, EdgePairsActInsideTheirSegmentsOrAtCornersNoParticleHoldsAndWithinTheRadius) {
  EXPECT_TRUE(law::edge_edge_interior(0.5, 0.5));
  EXPECT_FALSE(law::edge_edge_interior(0, 0.5));
  EXPECT_FALSE(law::edge_edge_interior(0.5, 1));
  // At an end whose corner is a particle, that corner's face contact pushes; a fixed corner has
  // none, so the edge pair keeps it.
  EXPECT_TRUE(law::edge_edge_acts(0.5, 0.5, true, true, true, true));
  EXPECT_FALSE(law::edge_edge_acts(0, 0.5, true, true, true, true));
  EXPECT_TRUE(law::edge_edge_acts(0, 0.5, false, true, true, true));
  EXPECT_FALSE(law::edge_edge_acts(0.5, 1, false, false, false, true));
  EXPECT_TRUE(law::edge_edge_acts(1, 1, false, false, true, false));
  EXPECT_EQ(law::contact_energy(0.04, 800, 0.03), 0);
  EXPECT_EQ(norm(law::stencil_contact_force({0, 0.04, 0}, {}, 800, 1, 0.03)), 0);
  EXPECT_EQ(norm(law::stencil_contact_force({0, 0, 0}, {}, 800, 1, 0.03)), 0);  // no direction
  // continuous at the radius: the force vanishes as d -> s
  EXPECT_NEAR(norm(law::stencil_contact_force({0, 0.03 - 1e-12, 0}, {}, 800, 0, 0.03)), 0, 1e-8);
}

}  // namespace
}  // namespace maille
