// Symplectic (semi-implicit) Euler: kick then drift, with full-step velocities.
//   v(n+1) = v(n) + h a(x_n, v_n);   x(n+1) = x(n) + h v(n+1)
// The same recurrence as leapfrog without the half-kick start, so velocities are first-order
// accurate but energy stays bounded (symplectic).
#include "integrators.hpp"

namespace maille {

namespace {

class SymplecticEuler final : public Integrator {
 public:
  std::string_view name() const override { return "symplectic_euler"; }
  void advance(const Model& m, State& s, Real h, ForceEvaluator&, Profile&) override {
    kick_drift(m, s, h, h, threads_);
  }
  std::optional<KickDrift> kick_drift_step(const State& s, Real h) const override {
    return KickDrift{h, h, s.history};
  }
  Amplification increment(double h, double w2, double c) const override {
    return kick_drift_increment(h, w2, c);
  }
};

}  // namespace

std::unique_ptr<Integrator> make_symplectic_euler() {
  return std::make_unique<SymplecticEuler>();
}

}  // namespace maille
