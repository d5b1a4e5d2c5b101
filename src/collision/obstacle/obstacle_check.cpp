// check_obstacle (include/maille/obstacle.hpp): an obstacle's validation, without building its
// stage (no facet grid, no surface samples). make_obstacle_stage relies on it; the scene table
// calls it to name the key at fault.
#include "obstacle_check.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "maille/limits.hpp"

#include "maille/obstacle.hpp"

namespace maille {

namespace {

// Positions are doubles: a threshold below 2^-50 of the coordinates has no meaning (and the cell
// index x / threshold would overflow a 64-bit integer).
constexpr double kFinestRelative = 0x1p-50;

std::string metres(double m) {
  char s[32];
  std::snprintf(s, sizeof s, "%.3g m", m);
  return s;
}

}  // namespace

std::string sampling_problem(const TriMesh& mesh, const shapes::Affine& place, Real spacing) {
  std::vector<Vec3> world(mesh.vertices.size());
  double reach = 0;
  for (std::size_t i = 0; i < world.size(); ++i) {
    const Vec3 x = world[i] = place.to_world(mesh.vertices[i]);
    reach = std::max({reach, double(std::abs(x.x)), double(std::abs(x.y)), double(std::abs(x.z))});
  }
  if (!(double(spacing) >= reach * kFinestRelative))
    return "the threshold " + metres(spacing) + " is below the precision of positions " +
           metres(reach) + " from the origin: raise threshold";
  double planned = 0;  // a count of 10^40 must not wrap around
  for (const auto& t : mesh.triangles) {
    const Vec3 &a = world[t[0]], &b = world[t[1]], &c = world[t[2]];
    const double d =
        std::ceil(double(std::max({norm(b - a), norm(c - b), norm(a - c)})) / double(spacing));
    planned += (d + 1) * (d + 2) / 2;
  }
  const double budget = double(limits::memory_budget_bytes());
  const double most = std::min(kMaxSurfaceSamples, budget / kBytesPerSample);
  if (planned <= most) return {};
  const double fits = double(spacing) * std::sqrt(planned / most) * 1.01;  // count ~ 1/s^2
  char why[320];
  std::snprintf(why, sizeof why,
                "sampling the surface at the threshold (%s) needs about %.3g points, more than "
                "%.3g (at most %.3g, and %.0f bytes each within the memory budget of %.3g GiB): "
                "raise threshold to %s or more",
                metres(spacing).c_str(), planned, most, kMaxSurfaceSamples, kBytesPerSample,
                budget / double(1 << 30), metres(fits).c_str());
  return why;
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
      if (const std::string why = sampling_problem(obstacle_mesh(o), o.place, o.threshold);
          !why.empty())
        return {"threshold", who + why};
      break;
  }
  return {};
}

}  // namespace maille
