// Floor: a horizontal grid of fixed points. With conditional links to a moving body it is the
// CORDIS way of making ground: a bed of spheres of radius `threshold`, which holds when the
// threshold exceeds half the diagonal spacing (no point can slip between four spheres).
#include <stdexcept>

#include "build_helpers.hpp"

namespace maille {

Group build_floor(Model& m, const FloorParams& p, const std::string& name) {
  if (p.nx < 2 || p.nz < 2) throw std::invalid_argument("floor resolution must be >= 2");
  const std::uint32_t first = m.points.size();
  const Real dx = p.width / Real(p.nx - 1), dz = p.depth / Real(p.nz - 1);
  const Vec3 corner = p.center - Vec3{p.width / 2, 0, p.depth / 2};
  for (std::uint32_t k = 0; k < p.nz; ++k)
    for (std::uint32_t i = 0; i < p.nx; ++i)
      m.points.add(PointKind::fixed, 1, corner + Vec3{Real(i) * dx, 0, Real(k) * dz});
  auto id = [&](std::uint32_t i, std::uint32_t k) { return first + k * p.nx + i; };
  for (std::uint32_t k = 0; k + 1 < p.nz; ++k)
    for (std::uint32_t i = 0; i + 1 < p.nx; ++i) {
      m.surface.triangles.push_back({id(i, k), id(i, k + 1), id(i + 1, k + 1)});
      m.surface.triangles.push_back({id(i, k), id(i + 1, k + 1), id(i + 1, k)});
    }
  return build::group(m, name, "floor", first);
}

}  // namespace maille
