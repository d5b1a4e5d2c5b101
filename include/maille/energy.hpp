// Energies of a state: what the tests check and stats.csv records.
#pragma once

#include <cstddef>
#include <span>

#include "maille/model.hpp"
#include "maille/state.hpp"

namespace maille {

struct Energies {
  double kinetic = 0;  // J, 1/2 m v^2 over free points
  double elastic = 0;  // J, potential stored in links
  double gravity = 0;  // J, -m g.x over free points (zero at the origin)
  // J, potential stored in contacts: the model's conditional links (`[[contact]] method =
  // "links"`, conditional obstacles' kind) and every stage's contacts (Stage::energy:
  // obstacles, self-collision, `[[contact]] method = "broad_phase"`), so that one physics
  // reports one energy whichever way its contacts are stored
  double contact = 0;
  double total() const { return kinetic + elastic + gravity + contact; }
};

// The energies by name, in stats.csv's column order: the stats writer, the Python module and
// the page read them here, so a new energy is one line.
template <class F>
void for_each_energy(const Energies& e, F&& f) {
  f("kinetic", e.kinetic);
  f("elastic", e.elastic);
  f("gravity", e.gravity);
  f("contact", e.contact);
  f("total", e.total());
}

inline constexpr std::size_t kEnergyColumns = 5;  // for_each_energy's calls (checked in tests)

// `velocity` is the velocity at the time of s.x (see Integrator::synchronized_velocity). The
// model's energies only: `contact` holds its conditional links; the simulator adds its stages'
// (Simulator::energies).
Energies compute_energies(const Model& m, const State& s, std::span<const Vec3> velocity);
double kinetic_energy(const Model& m, std::span<const Vec3> velocity);
Vec3 total_momentum(const Model& m, std::span<const Vec3> velocity);

}  // namespace maille
