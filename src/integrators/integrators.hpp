// Internal: factories of the built-in schemes and the loops they share.
#pragma once

#include <memory>

#include "maille/integrator.hpp"

namespace maille {

std::unique_ptr<Integrator> make_explicit_euler();
std::unique_ptr<Integrator> make_symplectic_euler();
std::unique_ptr<Integrator> make_leapfrog();
std::unique_ptr<Integrator> make_velocity_verlet();
std::unique_ptr<Integrator> make_rk4();
std::unique_ptr<Integrator> make_implicit_euler(const ImplicitSettings& settings);

// v += kick * f / m;  x += drift * v   on free points (inverse mass > 0).
void kick_drift(const Model& m, State& s, Real kick, Real drift, int threads);

// The kick-drift recurrence on the test equation (leapfrog, symplectic Euler):
// v' = v + h (-w2 x - c v), x' = x + h v'.
Amplification kick_drift_increment(double h, double w2, double c);

// Increments of composed stages: (I + a)(I + b) = I + a + b + ab.
Amplification compose(const Amplification& a, const Amplification& b);
Amplification multiply(const Amplification& a, const Amplification& b);

}  // namespace maille
