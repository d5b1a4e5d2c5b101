// Vec3 and the Real alias: the one place that decides the engine's floating-point width.
#pragma once

#include <cmath>
#include <cstdint>

namespace maille {

// Positions, velocities and forces are stored as double. Why (measured, see docs/architecture.md):
// float halves memory traffic, but the 10^5-step energy test and the h^2 convergence test of
// leapfrog need more than float's 7 digits once positions are O(1) m and steps O(1e-4) s
// (x + h*v loses the update below 1e-7 relative). Build with -DMAILLE_SINGLE_PRECISION=ON
// to measure the other side.
#ifdef MAILLE_SINGLE_PRECISION
using Real = float;
#else
using Real = double;
#endif

struct Vec3 {
  Real x = 0, y = 0, z = 0;

  constexpr Vec3() = default;
  constexpr Vec3(Real x_, Real y_, Real z_) : x(x_), y(y_), z(z_) {}

  constexpr Vec3& operator+=(const Vec3& o) {
    x += o.x;
    y += o.y;
    z += o.z;
    return *this;
  }
  constexpr Vec3& operator-=(const Vec3& o) {
    x -= o.x;
    y -= o.y;
    z -= o.z;
    return *this;
  }
  constexpr Vec3& operator*=(Real s) {
    x *= s;
    y *= s;
    z *= s;
    return *this;
  }
  constexpr Real operator[](int i) const { return i == 0 ? x : (i == 1 ? y : z); }
  constexpr bool operator==(const Vec3&) const = default;
};

// Loops may view an array of Vec3 as a flat array of 3n Reals.
static_assert(sizeof(Vec3) == 3 * sizeof(Real), "Vec3 must have no padding");

constexpr Vec3 operator+(Vec3 a, const Vec3& b) {
  return a += b;
}
constexpr Vec3 operator-(Vec3 a, const Vec3& b) {
  return a -= b;
}
constexpr Vec3 operator-(const Vec3& a) {
  return {-a.x, -a.y, -a.z};
}
constexpr Vec3 operator*(Vec3 a, Real s) {
  return a *= s;
}
constexpr Vec3 operator*(Real s, Vec3 a) {
  return a *= s;
}
constexpr Vec3 operator/(const Vec3& a, Real s) {
  return {a.x / s, a.y / s, a.z / s};
}
constexpr Real dot(const Vec3& a, const Vec3& b) {
  return a.x * b.x + a.y * b.y + a.z * b.z;
}
constexpr Vec3 cross(const Vec3& a, const Vec3& b) {
  return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}
constexpr Real norm2(const Vec3& a) {
  return dot(a, a);
}
inline Real norm(const Vec3& a) {
  return std::sqrt(dot(a, a));
}
inline bool is_finite(const Vec3& a) {
  return std::isfinite(a.x) && std::isfinite(a.y) && std::isfinite(a.z);
}

}  // namespace maille
