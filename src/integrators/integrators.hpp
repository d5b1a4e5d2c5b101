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

// A scheme whose whole step is one kick and one drift: kick_drift_step says which (and the
// history to keep), advance and the test equation's increment are written here once. Its own
// kick and drift are symplectic Euler's, h each with the history kept; leapfrog overrides them.
class KickDriftScheme : public Integrator {
 public:
  std::optional<KickDrift> kick_drift_step(const State& s, Real h) const override {
    return KickDrift{h, h, s.history};
  }
  void advance(const Model& m, State& s, Real h, ForceEvaluator&, Profile&) final {
    const KickDrift k = *kick_drift_step(s, h);
    kick_drift(m, s, k.kick, k.drift, threads_);
    s.history = k.history_after;
  }
  Amplification increment(double h, double w2, double c) const override {
    return kick_drift_increment(h, w2, c);
  }
};

// A scheme that evaluates the forces `Passes` times a step (the simulator's pass included), at
// intermediate states of its own: stages that rewrite forces or velocities after the fact
// (facet responses) cannot be combined with it (velocity Verlet, RK4).
template <int Passes>
class MultiPassScheme : public Integrator {
 public:
  int force_evaluations() const final { return Passes; }
  ResponseTiming response_timing() const final { return ResponseTiming::refused; }
};

// Increments of composed stages: (I + a)(I + b) = I + a + b + ab.
Amplification compose(const Amplification& a, const Amplification& b);
Amplification multiply(const Amplification& a, const Amplification& b);

}  // namespace maille
