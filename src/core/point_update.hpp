// Per-point formulas written once, so that the fused grid step (simulator_fused.cpp) computes
// exactly what the separate passes compute (field_forces.cpp, kick_drift in integrator.cpp).
#pragma once

#include "maille/vec3.hpp"

namespace maille::point_update {

// Gravity and air drag on a free point: m g - gamma m v (fixed points get nothing).
inline Vec3 field_force(const Vec3& g, Real gamma, Real mass, Real inv_mass, const Vec3& v) {
  const Real w = inv_mass > 0 ? mass : Real(0);
  return (g - v * gamma) * w;
}

// One kick and one drift: v += h_kick f / m, then x += h_drift v (free points only move).
inline void kick_drift(Vec3& x, Vec3& v, const Vec3& f, Real inv_mass, Real kick, Real drift) {
  const Real moves = inv_mass > 0 ? drift : Real(0);
  v += f * (inv_mass * kick);
  x += v * moves;
}

}  // namespace maille::point_update
