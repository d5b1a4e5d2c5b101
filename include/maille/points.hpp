// The points pool (PMat bricks): one struct-of-arrays record per material point.
#pragma once

#include <array>
#include <cstdint>
#include <string_view>
#include <vector>

#include "maille/names.hpp"
#include "maille/vec3.hpp"

namespace maille {

enum class PointKind : std::uint8_t {
  free,    // a mass, integrated by the scheme
  fixed,   // a fixed point: never moves (inverse mass 0)
  driven,  // a fixed point whose position follows a scripted path (see drive.hpp)
};

// As messages and frames name them ("mass" for a free point, as [[mass]] declares one).
template <>
struct NameTable<PointKind> {
  static constexpr std::string_view what = "point kind";
  static constexpr std::array<Name<PointKind>, 3> names{{
      {PointKind::free, "mass", "a mass, integrated by the scheme"},
      {PointKind::fixed, "fixed", "a fixed point"},
      {PointKind::driven, "driven", "a fixed point on a scripted path"},
  }};
};

// All arrays have one entry per point; index i is the point's id inside the engine.
struct PointPool {
  std::vector<Real> mass;              // [n] kg, > 0 (fixed points keep theirs for display only)
  std::vector<Real> inv_mass;          // [n] 1/kg; 0 for fixed and driven points
  std::vector<PointKind> kind;         // [n]
  std::vector<Vec3> initial_position;  // [n] m
  std::vector<Vec3> initial_velocity;  // [n] m/s (ignored for fixed points)

  std::uint32_t add(PointKind k, Real m, const Vec3& position, const Vec3& velocity = {});
  std::uint32_t size() const { return static_cast<std::uint32_t>(mass.size()); }
  std::uint32_t count(PointKind k) const;
  // Turns an existing point into a fixed or driven one (builders decide this after creation).
  void set_kind(std::uint32_t i, PointKind k);
};

}  // namespace maille
