#include "maille/contact_set.hpp"

#include "maille/link_loops.hpp"
#include "maille/mat3.hpp"

namespace maille {

void ContactSet::add_forces(std::span<const std::uint32_t> points, const Vec3* x, const Vec3* v,
                            Real inv_h, Vec3* f, Mat3* blocks) const {
  LinkCounters counters;
  for (const LinkPoolBase* pool : pairs_) accumulate_forces(*pool, x, v, f, counters);
  for (const TriangleContacts* t : stencils_) t->accumulate(x, v, f);
  for (const PointContacts* c : obstacles_) c->add_terms(points, x, v, inv_h, f, blocks, nullptr);
}

}  // namespace maille
