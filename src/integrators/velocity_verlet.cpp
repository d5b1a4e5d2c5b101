// Velocity Verlet, kick-drift-kick with full-step velocities:
//   v(n+1/2) = v(n) + h/2 a(x_n, v_n)
//   x(n+1)   = x(n) + h v(n+1/2)
//   v(n+1)   = v(n+1/2) + h/2 a(x_n+1, v(n+1/2))
// Second order in positions and velocities. With velocity-dependent forces (dampers, drag,
// wind) the closing kick needs a force pass at the new positions, so a step costs two passes
// (the simulator's own and this one) where leapfrog costs one.
#include "integrators.hpp"

namespace maille {

namespace {

class VelocityVerlet final : public MultiPassScheme<2> {
 public:
  std::string_view name() const override { return "velocity_verlet"; }

  void advance(const Model& m, State& s, Real h, ForceEvaluator& forces, Profile&) override {
    kick_drift(m, s, Real(0.5) * h, h, threads_);
    s.time += h;  // the closing kick's forces belong to t + h (driven points, gusts)
    forces.evaluate(s);
    s.time -= h;
    kick_drift(m, s, Real(0.5) * h, 0, threads_);
  }

  Amplification increment(double h, double w2, double c) const override {
    const Amplification kick{{{0, 0}, {-0.5 * h * w2, -0.5 * h * c}}};
    const Amplification drift{{{0, h}, {0, 0}}};
    return compose(kick, compose(drift, kick));
  }
};

}  // namespace

std::unique_ptr<Integrator> make_velocity_verlet() {
  return std::make_unique<VelocityVerlet>();
}

}  // namespace maille
