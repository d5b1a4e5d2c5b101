// check_obstacle (include/maille/obstacle.hpp): an obstacle's validation, without building its
// stage (no facet grid, no surface samples). make_obstacle_stage relies on it; the scene table
// calls it to name the key at fault.
#include "obstacle_check.hpp"

#include <algorithm>
#include <cmath>

#include "maille/obstacle.hpp"

namespace maille {

std::uint64_t planned_surface_samples(const TriMesh& mesh, const shapes::Affine& place,
                                      Real spacing) {
  std::uint64_t planned = 0;
  for (const auto& t : mesh.triangles) {
    const Vec3 a = place.to_world(mesh.vertices[t[0]]), b = place.to_world(mesh.vertices[t[1]]),
               c = place.to_world(mesh.vertices[t[2]]);
    const Real longest = std::max({norm(b - a), norm(c - b), norm(a - c)});
    const double divisions = std::ceil(double(longest / spacing));
    if (!(divisions < 1e7)) return kMaxSurfaceSamples + 1;  // also NaN: refused
    planned += std::uint64_t((divisions + 1) * (divisions + 2) / 2);
    if (planned > kMaxSurfaceSamples) return planned;
  }
  return planned;
}

StageProblem check_obstacle(const Model& m, const Obstacle& o) {
  const std::string who = "obstacle '" + o.name + "': ";
  for (const auto& name : o.collides_with)
    if (!m.group(name)) return {"collides_with", who + "no group named '" + name + "'"};
  std::vector<std::uint8_t> in(m.points.size(), o.collides_with.empty() ? 1 : 0);
  for (const auto& name : o.collides_with) {
    const Group* g = m.group(name);
    std::fill(in.begin() + g->first, in.begin() + g->first + g->count, 1);
  }
  bool any_free = false;
  for (std::uint32_t p = 0; p < m.points.size() && !any_free; ++p)
    any_free = in[p] && m.points.inv_mass[p] > 0;
  if (!any_free) return {"collides_with", who + "no free point collides with it"};
  switch (o.method) {
    case ObstacleMethod::geometric:
      if (o.mesh)
        return {"mesh", who +
                            "a mesh has no canonical distance; use method \"facets\" or "
                            "\"conditional\""};
      break;
    case ObstacleMethod::facets:
      if (o.mesh && o.mesh->triangles.empty()) return {"mesh", who + "the mesh has no facet"};
      break;
    case ObstacleMethod::conditional:
      // Canonical shapes are tessellated for the count (a mesh, not the stage's samples).
      if (planned_surface_samples(obstacle_mesh(o), o.place, o.threshold) > kMaxSurfaceSamples)
        return {"threshold", who + "sampling the surface at the threshold (" +
                                 std::to_string(o.threshold) + " m) would need more than " +
                                 std::to_string(kMaxSurfaceSamples) + " points: raise threshold"};
      break;
  }
  return {};
}

}  // namespace maille
