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

// The group of a grid builder, which records its grid's shape (the structured kernels read it).
inline Group grid_group(Model& m, const std::string& name, const std::string& builder,
                        std::uint32_t first, std::uint32_t nx, std::uint32_t ny) {
  Group g = group(m, name, builder, first);
  m.groups.back().grid_nx = g.grid_nx = nx;
  m.groups.back().grid_ny = g.grid_ny = ny;
  return g;
}

// A grid builder's points: nx x ny, point (i, j) at origin + along (i dx) + across (j dy) with
// index first + j nx + i (first: the model's size before), fixed where fixed(i, j) says.
template <class Fixed>
void grid_points(Model& m, const Vec3& origin, const Vec3& along, Real dx, const Vec3& across,
                 Real dy, std::uint32_t nx, std::uint32_t ny, Real point_mass, Fixed&& fixed) {
  for (std::uint32_t j = 0; j < ny; ++j)
    for (std::uint32_t i = 0; i < nx; ++i)
      m.points.add(fixed(i, j) ? PointKind::fixed : PointKind::free, point_mass,
                   origin + along * (Real(i) * dx) + across * (Real(j) * dy));
}

inline Vec3 unit(const Vec3& v) {
  const Real n = norm(v);
  return n > 0 ? v / n : v;
}

}  // namespace maille::build
