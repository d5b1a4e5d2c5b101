// The gust field: the vectorisable form (src/core/gust.hpp, used by WindField::at and the wind
// stage) gives the same bits as the original per-point formula, kept here as the reference.
#include <gtest/gtest.h>

#include <cmath>
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

TEST(Wind, GustFieldIsBitIdenticalToTheReferenceFormula) {
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> pos(-50, 50), time(0, 1000);
  const Vec3 winds[] = {{7, 0, 1.5}, {0, 3, 0}, {-2, 0.5, 4}, {0, 0, 0}};
  for (const Vec3& velocity : winds) {
    for (const Real turbulence : {Real(0), Real(0.35), Real(1.2)}) {
      WindField w;
      w.velocity = velocity;
      w.turbulence = turbulence;
      w.gust_frequency = Real(0.8);
      w.gust_wavelength = Real(1.5);
      for (int i = 0; i < 2000; ++i) {
        const Vec3 p{Real(pos(rng)), Real(pos(rng)), Real(pos(rng))};
        const double t = time(rng);
        const Vec3 got = w.at(p, t), want = reference_at(w, p, t);
        ASSERT_EQ(got.x, want.x) << i;
        ASSERT_EQ(got.y, want.y) << i;
        ASSERT_EQ(got.z, want.z) << i;
      }
    }
  }
}

// The sine itself, on the ranges the reduction folds (including the fold points, where the
// branch-free form must pick the same side as the branches).
TEST(Wind, GustSineMatchesAcrossFoldsAndLargeArguments) {
  constexpr double pi = std::numbers::pi;
  WindField w;
  w.velocity = {1, 0, 0};
  w.turbulence = 1;
  w.gust_wavelength = 1;
  w.gust_frequency = 1;
  // Along x at t = 0 the first sine's argument is -2 pi x: sweep it finely over many turns.
  for (double x = -40; x < 40; x += 1.0 / 1024 + 1e-9) {
    const Vec3 p{Real(x), 0, 0};
    ASSERT_EQ(w.at(p, 0).x, reference_at(w, p, 0).x) << x;
  }
  for (const double x : {pi / 4, pi / 2, -pi / 4, -pi / 2, pi / 8, 0.25, 0.5, -0.25, 1e6 + 0.25}) {
    const Vec3 p{Real(x), 0, 0};
    ASSERT_EQ(w.at(p, 0).x, reference_at(w, p, 0).x) << x;
  }
}

}  // namespace
}  // namespace maille
