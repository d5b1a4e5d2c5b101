// Internal helpers shared by the builders.
#pragma once

#include <cstdint>
#include <string>

#include "maille/builders.hpp"
#include "maille/links/spring_damper.hpp"

namespace maille::build {

// A spring-damper whose rest length is `rest_scale` times the current distance.
inline void link(Model& m, std::uint32_t a, std::uint32_t b, Real k, Real z, Real rest_scale = 1) {
  if (k <= 0) return;  // no stiffness: no link (a builder never makes bare dampers)
  const auto& x = m.points.initial_position;
  m.links.pool<SpringDamper>().add({a, b}, {k, norm(x[b] - x[a]) * rest_scale, z});
}

inline Group group(Model& m, const std::string& name, const std::string& builder,
                   std::uint32_t first) {
  Group g{name, builder, first, m.points.size() - first};
  m.groups.push_back(g);
  return g;
}

inline Vec3 unit(const Vec3& v) {
  const Real n = norm(v);
  return n > 0 ? v / n : v;
}

}  // namespace maille::build
