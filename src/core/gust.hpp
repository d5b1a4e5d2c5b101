// The gust field of WindField, split so that the wind stage can evaluate it in a vectorised loop.
// Internal to the core: WindField::at (wind.cpp) and the wind stage (field_forces.cpp) share it,
// so the two give the same bits.
//
// Why this shape: evaluated per face as WindField::at(p, t), the field rebuilt its basis (a norm,
// a cross product, a square root and four divisions) and ran four scalar sines with a branchy
// range reduction for every face: 80 % of the default scene's step. Here everything that does not
// depend on the point is computed once per evaluation of the forces (GustBasis), and the per-point
// part (gust_at) is branch-free and inlined, so the face loop vectorises (AVX-512: 8 faces at
// a time). Each operation is the one WindField::at always did, in the same order (only
// sub-expressions that depend on t alone are hoisted), so trajectories are bit-identical.
#pragma once

#include <numbers>

#include "maille/fields.hpp"

namespace maille::gust {

// sin(x) to 6e-8 absolute: reduce to [-pi, pi], fold to [-pi/2, pi/2], then the odd Taylor
// polynomial to x^11 (remainder (pi/2)^13 / 13! < 6e-8). Gusts need smoothness, not libm's last
// bit; this is the same on every platform. Branch-free so that loops calling it vectorise:
// - nearest integer by the magic-number trick (y + 1.5 2^52) - 1.5 2^52, which rounds to
//   nearest-even exactly as std::nearbyint does for |y| < 2^51 (|x| < 1.4e16 rad; beyond that
//   no reduction means anything);
// - the two folds as min/max: x > pi/2 becomes pi - x, x < -pi/2 becomes -pi - x, else x.
inline double sin(double x) {
  constexpr double pi = std::numbers::pi;
  constexpr double magic = 0x1.8p52;
  const double k = (x / (2 * pi) + magic) - magic;
  x -= 2 * pi * k;
  const double folded_high = pi - x;
  x = folded_high < x ? folded_high : x;
  const double folded_low = -pi - x;
  x = folded_low > x ? folded_low : x;
  const double x2 = x * x;
  return x * (1 + x2 * (-1.0 / 6 +
                        x2 * (1.0 / 120 +
                              x2 * (-1.0 / 5040 + x2 * (1.0 / 362880 + x2 * (-1.0 / 39916800))))));
}

// The point-independent part of the field at time t.
struct Basis {
  bool steady = true;        // no gusts (no wind or no turbulence): w = mean everywhere
  Vec3 mean{};               // U, m/s
  Vec3 u{}, e1{}, e2{};      // unit vectors: along U, across it (horizontal), and the third
  Real turbulence = 0;       // relative gust amplitude
  Real cross_amplitude = 0;  // turbulence |U|, m/s
  Real wavelength = 1;       // m
  double ft[4] = {};         // f t times each sine's frequency factor (1, 1.73, 1.37, 0.61)
};

inline Basis basis(const WindField& w, double t) {
  Basis b;
  b.mean = w.velocity;
  const Real speed = norm(w.velocity);
  if (speed == 0 || w.turbulence == 0) return b;
  b.steady = false;
  b.u = w.velocity / speed;
  Vec3 e1 = cross(b.u, Vec3{0, 1, 0});
  if (norm2(e1) < Real(1e-12)) e1 = Vec3{1, 0, 0};
  b.e1 = e1 / norm(e1);
  b.e2 = cross(b.e1, b.u);
  b.turbulence = w.turbulence;
  b.cross_amplitude = w.turbulence * speed;
  b.wavelength = w.gust_wavelength;
  const double ft = w.gust_frequency * t;
  b.ft[0] = ft;
  b.ft[1] = 1.73 * ft;
  b.ft[2] = 1.37 * ft;
  b.ft[3] = 0.61 * ft;
  return b;
}

// Gusts are a fixed sum of travelling sines along the wind and across it: smooth in space and
// time, deterministic (same scene, same trajectory), and rich enough that a flag never settles.
// The incommensurate factors (1.73, 1.37, 0.61) keep the pattern from repeating quickly.
// Requires !b.steady (then the field is b.mean).
inline Vec3 at(const Basis& b, const Vec3& p) {
  constexpr double tau = 2 * std::numbers::pi;
  const double s = dot(b.u, p) / b.wavelength, q = dot(b.e2, p) / b.wavelength;
  const double g = 0.6 * gust::sin(tau * (b.ft[0] - s)) +
                   0.4 * gust::sin(tau * (b.ft[1] - 1.31 * s + 0.5 * q) + 1.1);
  const double c1 = 0.5 * gust::sin(tau * (b.ft[2] - 0.8 * s + 0.3 * q) + 0.7);
  const double c2 = 0.3 * gust::sin(tau * (b.ft[3] - 1.2 * s) + 2.1);
  return b.mean * Real(1 + b.turbulence * g) +
         (b.e1 * Real(c1) + b.e2 * Real(c2)) * b.cross_amplitude;
}

}  // namespace maille::gust
