// Fields: forces that act on every point (gravity, air drag) or on every cloth face (wind).
#pragma once

#include <span>

#include "maille/vec3.hpp"

namespace maille {

template <class S>
struct StageKey;  // stage_keys.hpp

// Wind acting on surface triangles through their normal and the relative air velocity:
//   v_rel = w(x_c, t) - (v_a + v_b + v_c)/3,  v_n = (v_rel . n) n
//   F = 1/2 rho C_d A |v_rel . n| (v_rel . n) n, shared equally by the three corners.
// Pressure acts only along the normal (a thin plate), and the sign follows the side the air comes
// from, so a face edge-on to the wind feels nothing and a face flapping into it feels more.
// Gusts: w = U (1 + turbulence * g(x, t)) + turbulence |U| * c(x, t) with g, c smooth sums of
// travelling sines (deterministic), so a flag flutters instead of settling into a static sail.
struct WindField {
  Vec3 velocity{};            // U, mean wind velocity, m/s
  Real density = Real(1.2);   // rho, air density, kg/m^3
  Real drag_coefficient = 1;  // C_d, pressure coefficient of a face, dimensionless
  Real turbulence = 0;        // relative gust amplitude, dimensionless, >= 0
  Real gust_frequency = 1;    // Hz
  Real gust_wavelength = 2;   // m

  bool active() const { return norm2(velocity) > 0 || turbulence > 0; }
  Vec3 at(const Vec3& p, double t) const;
};

// [fields.wind]'s keys (src/core/wind_keys.cpp).
std::span<const StageKey<WindField>> wind_keys();

struct Fields {
  Vec3 gravity{0, Real(-9.81), 0};  // g, m/s^2
  Real air_drag = 0;                // gamma, 1/s: f = -gamma m v on every free point
  WindField wind;
};

}  // namespace maille
