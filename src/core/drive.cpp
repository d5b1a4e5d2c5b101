#include <algorithm>
#include <cmath>
#include <numbers>

#include "maille/drive.hpp"

namespace maille {

namespace {
constexpr double kTau = 2 * std::numbers::pi;

// Two unit vectors perpendicular to the axis and to each other (the circle's plane).
void plane_basis(const Vec3& axis, Vec3& u, Vec3& w) {
  const Vec3 a = axis / norm(axis);
  u = std::abs(a.x) < 0.9 ? cross(a, Vec3{1, 0, 0}) : cross(a, Vec3{0, 1, 0});
  u = u / norm(u);
  w = cross(a, u);
}

// Index of the key segment holding t (keys sorted by time, at least two).
std::size_t segment(const std::vector<std::pair<double, Vec3>>& keys, double t) {
  auto it = std::upper_bound(keys.begin(), keys.end(), t,
                             [](double v, const auto& k) { return v < k.first; });
  const auto i = static_cast<std::size_t>(it - keys.begin());
  return std::clamp<std::size_t>(i, 1, keys.size() - 1) - 1;
}
// Rodrigues: v rotated by `angle` about the unit axis k.
Vec3 rotated(const Vec3& v, const Vec3& k, double angle) {
  const Real c = Real(std::cos(angle)), s = Real(std::sin(angle));
  return v * c + cross(k, v) * s + k * (dot(k, v) * (1 - c));
}

// The rotate path's rate factor a for a point starting at x0 (see drive.hpp).
Real twist_factor(const DrivePath& p, const Vec3& k) {
  if (p.length <= 0) return 1;
  return std::clamp(dot(p.origin - p.center, k) / p.length, Real(-1), Real(1));
}
}  // namespace

Vec3 DrivePath::position(double t) const {
  const double a = kTau * frequency * t + phase;
  switch (kind) {
    case Kind::sine:
      return origin + amplitude * Real(std::sin(a) - std::sin(phase));
    case Kind::circle: {
      Vec3 u, w;
      plane_basis(axis, u, w);
      return origin +
             (u * Real(std::cos(a) - std::cos(phase)) + w * Real(std::sin(a) - std::sin(phase))) *
                 radius;
    }
    case Kind::keyframes: {
      if (keys.empty()) return origin;
      if (t <= keys.front().first) return keys.front().second;
      if (t >= keys.back().first) return keys.back().second;
      const std::size_t i = segment(keys, t);
      const auto& [t0, x0] = keys[i];
      const auto& [t1, x1] = keys[i + 1];
      return x0 + (x1 - x0) * Real((t - t0) / (t1 - t0));
    }
    case Kind::rotate: {
      const Vec3 k = axis / norm(axis);
      return center + rotated(origin - center, k, kTau * frequency * t * twist_factor(*this, k));
    }
  }
  return origin;
}

Vec3 DrivePath::velocity(double t) const {
  const double a = kTau * frequency * t + phase;
  const double da = kTau * frequency;
  switch (kind) {
    case Kind::sine:
      return amplitude * Real(da * std::cos(a));
    case Kind::circle: {
      Vec3 u, w;
      plane_basis(axis, u, w);
      return (u * Real(-std::sin(a)) + w * Real(std::cos(a))) * Real(radius * da);
    }
    case Kind::keyframes: {
      if (keys.size() < 2 || t < keys.front().first || t >= keys.back().first) return {};
      const std::size_t i = segment(keys, t);
      return (keys[i + 1].second - keys[i].second) / Real(keys[i + 1].first - keys[i].first);
    }
    case Kind::rotate: {
      const Vec3 k = axis / norm(axis);
      const Real w = Real(kTau * frequency) * twist_factor(*this, k);
      return cross(k * w, position(t) - center);
    }
  }
  return {};
}

Real DrivePath::max_speed() const {
  switch (kind) {
    case Kind::sine:
      return Real(kTau * frequency) * norm(amplitude);
    case Kind::circle:
      return Real(kTau * frequency) * radius;
    case Kind::rotate: {
      const Vec3 k = axis / norm(axis);
      const Vec3 r = origin - center;
      return Real(kTau * frequency) * std::abs(twist_factor(*this, k)) * norm(r - k * dot(k, r));
    }
    case Kind::keyframes: {
      Real top = 0;
      for (std::size_t i = 0; i + 1 < keys.size(); ++i)
        top = std::max(top, norm(keys[i + 1].second - keys[i].second) /
                                Real(keys[i + 1].first - keys[i].first));
      return top;
    }
  }
  return 0;
}

}  // namespace maille
