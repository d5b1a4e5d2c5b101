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
  void advance(const Model& m, State& s, Real h, ForceEvaluator&) override {
    kick_drift(m, s, h, h, threads_);
  }
  Real stable_step(Real omega2, Real c) const override { return kick_drift_stable_step(omega2, c); }
};

}  // namespace

std::unique_ptr<Integrator> make_symplectic_euler() {
  return std::make_unique<SymplecticEuler>();
}

}  // namespace maille
