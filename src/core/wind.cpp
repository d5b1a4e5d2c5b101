#include <cmath>
#include <numbers>

#include "maille/fields.hpp"

namespace maille {

namespace {

// sin(x) to 6e-8 absolute for any x: reduce to [-pi, pi], fold to [-pi/2, pi/2], then the odd
// Taylor polynomial to x^11 (remainder (pi/2)^13 / 13! < 6e-8). Gusts need smoothness, not libm's
// last bit, and this is ~5x cheaper per face; it is also the same on every platform.
double gust_sin(double x) {
  constexpr double pi = std::numbers::pi;
  x -= 2 * pi * std::nearbyint(x / (2 * pi));
  if (x > pi / 2) x = pi - x;
  if (x < -pi / 2) x = -pi - x;
  const double x2 = x * x;
  return x * (1 + x2 * (-1.0 / 6 +
                        x2 * (1.0 / 120 +
                              x2 * (-1.0 / 5040 + x2 * (1.0 / 362880 + x2 * (-1.0 / 39916800))))));
}

}  // namespace

// Gusts are a fixed sum of travelling sines along the wind and across it: smooth in space and
// time, deterministic (same scene, same trajectory), and rich enough that a flag never settles.
// The incommensurate factors (1.73, 1.37, 0.61) keep the pattern from repeating quickly.
Vec3 WindField::at(const Vec3& p, double t) const {
  const Real speed = norm(velocity);
  if (speed == 0 || turbulence == 0) return velocity;
  const Vec3 u = velocity / speed;
  Vec3 e1 = cross(u, Vec3{0, 1, 0});
  if (norm2(e1) < Real(1e-12)) e1 = Vec3{1, 0, 0};
  e1 = e1 / norm(e1);
  const Vec3 e2 = cross(e1, u);
  constexpr double tau = 2 * std::numbers::pi;
  const double s = dot(u, p) / gust_wavelength, q = dot(e2, p) / gust_wavelength;
  const double ft = gust_frequency * t;
  const double g =
      0.6 * gust_sin(tau * (ft - s)) + 0.4 * gust_sin(tau * (1.73 * ft - 1.31 * s + 0.5 * q) + 1.1);
  const double c1 = 0.5 * gust_sin(tau * (1.37 * ft - 0.8 * s + 0.3 * q) + 0.7);
  const double c2 = 0.3 * gust_sin(tau * (0.61 * ft - 1.2 * s) + 2.1);
  return velocity * Real(1 + turbulence * g) +
         (e1 * Real(c1) + e2 * Real(c2)) * (turbulence * speed);
}

}  // namespace maille
