#include "maille/energy.hpp"

namespace maille {

double kinetic_energy(const Model& m, std::span<const Vec3> velocity) {
  double k = 0;
  for (std::size_t i = 0; i < velocity.size(); ++i)
    if (m.points.inv_mass[i] > 0) k += 0.5 * m.points.mass[i] * norm2(velocity[i]);
  return k;
}

Vec3 total_momentum(const Model& m, std::span<const Vec3> velocity) {
  Vec3 p{};
  for (std::size_t i = 0; i < velocity.size(); ++i)
    if (m.points.inv_mass[i] > 0) p += velocity[i] * m.points.mass[i];
  return p;
}

Energies compute_energies(const Model& m, const State& s, std::span<const Vec3> velocity) {
  Energies e;
  e.kinetic = kinetic_energy(m, velocity);
  for (const auto& pool : m.links.pools())
    (pool->conditional() ? e.contact : e.elastic) += pool->energy(s.x().data());
  const auto x = s.x();
  for (std::size_t i = 0; i < x.size(); ++i)
    if (m.points.inv_mass[i] > 0) e.gravity -= m.points.mass[i] * dot(m.fields.gravity, x[i]);
  return e;
}

}  // namespace maille
