// The force stages of the step, one file each (clear_forces.cpp, link_forces.cpp,
// field_forces.cpp). Internal: the simulator calls them; tests reach them through it.
#pragma once

#include "maille/link_set.hpp"
#include "maille/model.hpp"
#include "maille/state.hpp"

namespace maille::stages {

void clear_forces(State& s);
// Returns the number of active conditional links.
LinkCounters link_forces(const Model& m, State& s, int threads);
// Gravity and air drag on points, wind on faces. Returns the number of faces the wind pushed.
std::uint64_t field_forces(const Model& m, State& s, int threads);
void drive(const Model& m, State& s, double t);

}  // namespace maille::stages
