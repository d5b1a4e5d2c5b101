// Scripted paths for driven fixed points (a pole that shakes, a hand that swings a rope).
#pragma once

#include <cstdint>
#include <utility>
#include <vector>

#include "maille/names.hpp"
#include "maille/vec3.hpp"

namespace maille {

struct DrivePath {
  enum class Kind : std::uint8_t {
    sine,       // x(t) = x0 + amplitude * sin(2 pi f t + phase)
    circle,     // x(t) = x0 + radius * (cos(2 pi f t + phase) - 1) u + radius * sin(...) w,
                //   u, w orthonormal and perpendicular to `axis`; starts at x0
    keyframes,  // piecewise linear through (t, x) keys; held at the ends
    rotate,     // x(t) = c + R(axis, 2 pi f t a) (x0 - c): a rotation about the line through
                //   `center` along `axis`; a = 1, or, with a `length`, the point's axial
                //   coordinate over it, clamped to [-1, 1] (a twist: wringing a cloth)
  };
  Kind kind = Kind::sine;
  Vec3 origin{};                              // x0, m (the point's scene position)
  Vec3 amplitude{};                           // m (sine)
  Vec3 axis{0, 1, 0};                         // rotation axis (circle, rotate)
  Vec3 center{};                              // m, a point of the rotation axis (rotate)
  Real length = 0;                            // m, twist length (rotate); 0: rigid rotation
  Real radius = 0;                            // m (circle)
  Real frequency = 0;                         // Hz
  Real phase = 0;                             // rad
  std::vector<std::pair<double, Vec3>> keys;  // (s, m), increasing times (keyframes)

  Vec3 position(double t) const;
  Vec3 velocity(double t) const;
  Real max_speed() const;  // m/s, over all times
};

template <>
struct NameTable<DrivePath::Kind> {
  static constexpr std::string_view what = "drive path";
  static constexpr std::array<Name<DrivePath::Kind>, 4> names{{
      {DrivePath::Kind::sine, "sine", "x0 + A (sin(2 pi f t + phase) - sin phase)"},
      {DrivePath::Kind::circle, "circle", "a circle of `radius` about `axis`, from x0"},
      {DrivePath::Kind::keyframes, "keyframes", "piecewise linear through the keys"},
      {DrivePath::Kind::rotate, "rotate", "about the line through `center` along `axis`"},
  }};
};

struct Drive {
  std::uint32_t point = 0;
  DrivePath path;
};

}  // namespace maille
