// The gust field: the vectorisable form (src/core/gust.hpp, used by WindField::at and the wind
// stage) against the original per-point formula, kept here as the reference. The sines'
// polynomial runs in float there (their arguments are reduced in double first), so the two agree
// to float rounding, not bit for bit.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <random>

#include "maille/fields.hpp"

namespace maille {
namespace {

// The field as first written: basis rebuilt per point, nearbyint and branches in the sine.
double reference_sin(double x) {
  constexpr double pi = std::numbers::pi;
  x -= 2 * pi * std::nearbyint(x / (2 * pi));
  if (x > pi / 2) x = pi - x;
  if (x < -pi / 2) x = -pi - x;
  const double x2 = x * x;
  return x * (1 + x2 * (-1.0 / 6 +
                        x2 * (1.0 / 120 +
                              x2 * (-1.0 / 5040 + x2 * (1.0 / 362880 + x2 * (-1.0 / 39916800))))));
}

Vec3 reference_at(const WindField& w, const Vec3& p, double t) {
  const Real speed = norm(w.velocity);
  if (speed == 0 || w.turbulence == 0) return w.velocity;
  const Vec3 u = w.velocity / speed;
  Vec3 e1 = cross(u, Vec3{0, 1, 0});
  if (norm2(e1) < Real(1e-12)) e1 = Vec3{1, 0, 0};
  e1 = e1 / norm(e1);
  const Vec3 e2 = cross(e1, u);
  constexpr double tau = 2 * std::numbers::pi;
  const double s = dot(u, p) / w.gust_wavelength, q = dot(e2, p) / w.gust_wavelength;
  const double ft = w.gust_frequency * t;
  const double g = 0.6 * reference_sin(tau * (ft - s)) +
                   0.4 * reference_sin(tau * (1.73 * ft - 1.31 * s + 0.5 * q) + 1.1);
  const double c1 = 0.5 * reference_sin(tau * (1.37 * ft - 0.8 * s + 0.3 * q) + 0.7);
  const double c2 = 0.3 * reference_sin(tau * (0.61 * ft - 1.2 * s) + 2.1);
  return w.velocity * Real(1 + w.turbulence * g) +
         (e1 * Real(c1) + e2 * Real(c2)) * (w.turbulence * speed);
}

// Tolerance of the float sines. Per sine: the reduced argument rounded once to float (at most
// 2^-25 turn on |r| <= 1/2: 1.9e-7 on the sine), then the polynomial's eleven float operations
// on values at most pi/2 (a few float roundings of at most 2^-24 relative each: < 3e-7 in
// all); the reference formula's own error (the same truncated polynomial, 6e-8) cancels. Bound:
// 5e-7 per sine. The gust sums four sines with the weights of the formula, 0.6 T U + 0.4 T U +
// 0.5 T |U| + 0.3 T |U| = 1.8 T |U| in all, in float (amplitudes rounded to float: 6e-8
// relative, and three additions): 1e-6 x 1.8 T |U| per component bounds it with room.
double gust_tolerance(const WindField& w) {
  return 1e-6 * 1.8 * w.turbulence * norm(w.velocity) + 1e-12 * norm(w.velocity);
}

TEST(Wind, GustFieldMatchesTheReferenceFormula) {
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> pos(-50, 50), time(0, 1000);
  const Vec3 winds[] = {{7, 0, 1.5}, {0, 3, 0}, {-2, 0.5, 4}, {0, 0, 0}};
  double worst = 0;  // largest error in units of 1.8 T |U|
  for (const Vec3& velocity : winds) {
    for (const Real turbulence : {Real(0), Real(0.35), Real(1.2)}) {
      WindField w;
      w.velocity = velocity;
      w.turbulence = turbulence;
      w.gust_frequency = Real(0.8);
      w.gust_wavelength = Real(1.5);
      const double tolerance = gust_tolerance(w);
      for (int i = 0; i < 2000; ++i) {
        const Vec3 p{Real(pos(rng)), Real(pos(rng)), Real(pos(rng))};
        const double t = time(rng);
        const Vec3 got = w.at(p, t), want = reference_at(w, p, t);
        if (turbulence == 0 || norm(velocity) == 0) {  // steady: exactly U
          ASSERT_EQ(got, want) << i;
          continue;
        }
        for (int axis = 0; axis < 3; ++axis) {
          const double error = std::abs(got[axis] - want[axis]);
          ASSERT_LE(error, tolerance) << i << ' ' << axis;
          worst = std::max(worst, error / (1.8 * turbulence * norm(velocity)));
        }
      }
    }
  }
  char text[32];
  std::snprintf(text, sizeof text, "%.3g", worst);
  RecordProperty("worst_error_per_unit_amplitude", text);
  EXPECT_GT(worst, 0);  // float really is used (the bound is not vacuous by accident)
}

// The sine itself, on the ranges the reduction folds (including the fold points, where the
// branch-free form must pick the same side as the branches), and far from the origin.
TEST(Wind, GustSineMatchesAcrossFoldsAndLargeArguments) {
  constexpr double pi = std::numbers::pi;
  WindField w;
  w.velocity = {1, 0, 0};
  w.turbulence = 1;
  w.gust_wavelength = 1;
  w.gust_frequency = 1;
  const double tolerance = gust_tolerance(w);
  // Along x at t = 0 the first sine's argument is -2 pi x: sweep it finely over many turns.
  for (double x = -40; x < 40; x += 1.0 / 1024 + 1e-9) {
    const Vec3 p{Real(x), 0, 0};
    ASSERT_NEAR(w.at(p, 0).x, reference_at(w, p, 0).x, tolerance) << x;
  }
  for (const double x : {pi / 4, pi / 2, -pi / 4, -pi / 2, pi / 8, 0.25, 0.5, -0.25, 1e6 + 0.25}) {
    const Vec3 p{Real(x), 0, 0};
    ASSERT_NEAR(w.at(p, 0).x, reference_at(w, p, 0).x, tolerance) << x;
  }
}

}  // namespace
}  // namespace maille
