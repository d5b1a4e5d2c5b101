// Internal helpers shared by the builders.
#pragma once

#include <cstdint>
#include <stdexcept>
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

inline Vec3 unit(const Vec3& v) {
  const Real n = norm(v);
  return n > 0 ? v / n : v;
}

// A grid builder's points, built by grid_points: point (i, j) has index first + j nx + i.
struct Grid {
  std::uint32_t first, nx, ny;
  std::uint32_t operator()(std::uint32_t i, std::uint32_t j) const { return first + j * nx + i; }
};

// A grid builder's points: nx x ny (at least 2 x 2, else "<builder> resolution must be >= 2")
// spanning width along `along` and height along `across` (both normalised) from `origin`, the
// mass shared equally, fixed where fixed(i, j) says; first: the model's size before.
template <class Fixed>
Grid grid_points(Model& m, const std::string& builder, const Vec3& origin, const Vec3& along,
                 Real width, const Vec3& across, Real height, std::uint32_t nx, std::uint32_t ny,
                 Real mass, Fixed&& fixed) {
  if (nx < 2 || ny < 2) throw std::invalid_argument(builder + " resolution must be >= 2");
  const Grid g{m.points.size(), nx, ny};
  const Vec3 u = unit(along), w = unit(across);
  const Real dx = width / Real(nx - 1), dy = height / Real(ny - 1);
  const Real point_mass = mass / Real(nx * ny);
  for (std::uint32_t j = 0; j < ny; ++j)
    for (std::uint32_t i = 0; i < nx; ++i)
      m.points.add(fixed(i, j) ? PointKind::fixed : PointKind::free, point_mass,
                   origin + u * (Real(i) * dx) + w * (Real(j) * dy));
  return g;
}

}  // namespace maille::build
