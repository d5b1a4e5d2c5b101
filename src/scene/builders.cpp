// Contacts between groups: the CORDIS way of making two bodies (or a body and a floor) collide,
// with one conditional link per pair of points.
#include <stdexcept>

#include "build_helpers.hpp"
#include "maille/links/conditional.hpp"

namespace maille {

std::size_t build_contacts(Model& m, const Group& a, const Group& b, const ContactParams& p) {
  auto& pool = m.links.pool<ConditionalSpringDamper>();
  const Real rest = p.rest_length < 0 ? p.threshold : p.rest_length;
  std::size_t added = 0;
  for (std::uint32_t i = a.first; i < a.first + a.count; ++i)
    for (std::uint32_t j = b.first; j < b.first + b.count; ++j) {
      if (i == j || (m.points.inv_mass[i] == 0 && m.points.inv_mass[j] == 0)) continue;
      pool.add({i, j}, {p.stiffness, p.damping, p.threshold, rest});
      ++added;
    }
  return added;
}

}  // namespace maille
