// Energies of a state: what the tests check and stats.csv records.
#pragma once

#include <span>

#include "maille/model.hpp"
#include "maille/state.hpp"

namespace maille {

struct Energies {
  double kinetic = 0;  // J, 1/2 m v^2 over free points
  double elastic = 0;  // J, potential stored in links
  double gravity = 0;  // J, -m g.x over free points (zero at the origin)
  double total() const { return kinetic + elastic + gravity; }
};

// `velocity` is the velocity at the time of s.x (see Integrator::synchronized_velocity).
Energies compute_energies(const Model& m, const State& s, std::span<const Vec3> velocity);
double kinetic_energy(const Model& m, std::span<const Vec3> velocity);
Vec3 total_momentum(const Model& m, std::span<const Vec3> velocity);

}  // namespace maille
