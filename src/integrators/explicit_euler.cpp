// Explicit (forward) Euler: both updates from the state at t_n.
//   x(n+1) = x(n) + h v(n);   v(n+1) = v(n) + h a(x_n, v_n)
// First order and not symplectic: on an undamped oscillator the energy grows by (1 + (wh)^2)
// every step, so no step is stable without damping. Kept as the textbook reference.
#include <cstdint>

#include "integrators.hpp"

namespace maille {

namespace {

class ExplicitEuler final : public Integrator {
 public:
  std::string_view name() const override { return "explicit_euler"; }
  bool drifts_after_kick() const override { return false; }  // x moves with v_n
  void advance(const Model& m, State& s, Real h, ForceEvaluator&, Profile&) override {
    const Real* inv_mass = m.points.inv_mass.data();
    const Vec3* f = s.f().data();
    Vec3* v = s.v().data();
    Vec3* x = s.x().data();
    const auto n = static_cast<std::int64_t>(s.size());
#pragma omp parallel for schedule(static) num_threads(threads_) if (threads_ > 1)
    for (std::int64_t i = 0; i < n; ++i) {
      const Real w = inv_mass[i];
      x[i] += v[i] * (w > 0 ? h : Real(0));
      v[i] += f[i] * (w * h);
    }
  }
  Amplification increment(double h, double w2, double c) const override {
    return {{{0, h}, {-h * w2, -h * c}}};
  }
};

}  // namespace

std::unique_ptr<Integrator> make_explicit_euler() {
  return std::make_unique<ExplicitEuler>();
}

}  // namespace maille
