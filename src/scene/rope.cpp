// Rope (or chain): points on a segment, neighbours joined by spring-dampers, optionally every
// other point too (bending), one or both ends fixed; with a pretension, rest lengths shorter than
// the built spacing (a string stretched between fixed ends).
#include <stdexcept>

#include "build_helpers.hpp"

namespace maille {

Group build_rope(Model& m, const RopeParams& p, const std::string& name) {
  if (p.points < 2) throw std::invalid_argument("rope needs >= 2 points");
  const std::uint32_t first = m.points.size();
  const Real point_mass = p.mass / Real(p.points);
  for (std::uint32_t i = 0; i < p.points; ++i) {
    const bool at_start = i == 0, at_end = i + 1 == p.points;
    const bool fixed = (at_start && (p.fixed == RopeFixed::start || p.fixed == RopeFixed::both)) ||
                       (at_end && (p.fixed == RopeFixed::end || p.fixed == RopeFixed::both));
    const Real s = Real(i) / Real(p.points - 1);
    m.points.add(fixed ? PointKind::fixed : PointKind::free, point_mass,
                 p.start + (p.end - p.start) * s);
  }
  for (std::uint32_t i = 0; i + 1 < p.points; ++i) {
    build::link(m, first + i, first + i + 1, p.material.stiffness, p.material.damping,
                1 - p.pretension);
    if (i + 2 < p.points)
      build::link(m, first + i, first + i + 2, p.bending_stiffness, p.material.damping,
                  1 - p.pretension);
  }
  return build::group(m, name, "rope", first);
}

}  // namespace maille
