// Internal: factories of the built-in schemes and the loop they share.
#pragma once

#include <memory>

#include "maille/integrator.hpp"

namespace maille {

std::unique_ptr<Integrator> make_leapfrog();
std::unique_ptr<Integrator> make_symplectic_euler();

// v += kick * f / m;  x += drift * v   on free points (inverse mass > 0).
void kick_drift(const Model& m, State& s, Real kick, Real drift, int threads);

}  // namespace maille
