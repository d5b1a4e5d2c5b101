// Membrane: a drum skin. Points on a triangular lattice clipped to a disk, every lattice
// neighbour joined; a point missing any of its six neighbours is on the boundary and is fixed,
// so the boundary is closed all the way round.
//
//   lattice (a, b) -> centre + s (a u + b w),  u = (1, 0),  w = (1/2, sqrt(3)/2)
//   neighbours: +-u, +-w, +-(w - u);  faces: (a,b)(a+1,b)(a,b+1) and (a+1,b)(a+1,b+1)(a,b+1)
#include <cmath>
#include <map>
#include <stdexcept>
#include <utility>

#include "build_helpers.hpp"

namespace maille {

Group build_membrane(Model& m, const MembraneParams& p, const std::string& name) {
  if (p.rings < 2) throw std::invalid_argument("membrane needs rings >= 2");
  const Vec3 n = build::unit(p.normal);
  Vec3 e1 =
      build::unit(std::abs(n.x) < Real(0.9) ? cross(n, Vec3{1, 0, 0}) : cross(n, Vec3{0, 1, 0}));
  const Vec3 e2 = cross(n, e1);
  const Real s = p.radius / Real(p.rings - 1);
  const Vec3 u = e1 * s, w = (e1 * Real(0.5) + e2 * Real(std::sqrt(3.0) / 2)) * s;
  const int r = static_cast<int>(p.rings) + 1;
  auto inside = [&](int a, int b) {
    return norm(u * Real(a) + w * Real(b)) <= p.radius * (1 + Real(1e-9));
  };
  // Lattice coordinates of every point inside the disk, in a fixed order.
  std::map<std::pair<int, int>, std::uint32_t> index;
  const std::uint32_t first = m.points.size();
  std::uint32_t free_count = 0;
  std::vector<std::pair<int, int>> cells;
  for (int b = -r; b <= r; ++b)
    for (int a = -2 * r; a <= 2 * r; ++a)
      if (inside(a, b)) cells.push_back({a, b});
  const int da[6] = {1, -1, 0, 0, -1, 1}, db[6] = {0, 0, 1, -1, 1, -1};
  std::vector<bool> boundary(cells.size());
  for (std::size_t c = 0; c < cells.size(); ++c) {
    for (int k = 0; k < 6; ++k)
      if (!inside(cells[c].first + da[k], cells[c].second + db[k])) boundary[c] = true;
    if (!boundary[c]) ++free_count;
  }
  if (free_count == 0) throw std::invalid_argument("membrane has no free point: raise rings");
  const Real point_mass = p.mass / Real(free_count);
  for (std::size_t c = 0; c < cells.size(); ++c) {
    const auto [a, b] = cells[c];
    index[cells[c]] = m.points.add(boundary[c] ? PointKind::fixed : PointKind::free, point_mass,
                                   p.center + u * Real(a) + w * Real(b));
  }
  auto at = [&](int a, int b) -> std::int64_t {
    auto it = index.find({a, b});
    return it == index.end() ? std::int64_t{-1} : std::int64_t{it->second};
  };
  const Real rest_scale = 1 - p.pretension;
  for (const auto& [a, b] : cells) {
    const auto i = static_cast<std::uint32_t>(at(a, b));
    for (const auto& [na, nb] : {std::pair{a + 1, b}, std::pair{a, b + 1}, std::pair{a - 1, b + 1}})
      if (at(na, nb) >= 0)
        build::link(m, i, static_cast<std::uint32_t>(at(na, nb)), p.material.stiffness,
                    p.material.damping, rest_scale);
    const auto p10 = at(a + 1, b), p01 = at(a, b + 1), p11 = at(a + 1, b + 1);
    if (p10 >= 0 && p01 >= 0)
      m.surface.triangles.push_back(
          {i, static_cast<std::uint32_t>(p10), static_cast<std::uint32_t>(p01)});
    if (p10 >= 0 && p01 >= 0 && p11 >= 0)
      m.surface.triangles.push_back({static_cast<std::uint32_t>(p10),
                                     static_cast<std::uint32_t>(p11),
                                     static_cast<std::uint32_t>(p01)});
  }
  return build::group(m, name, "membrane", first);
}

}  // namespace maille
