// Leapfrog in the CORDIS style: velocities live at half steps.
//   v(n+1/2) = v(n-1/2) + h a(x_n, v(n-1/2))
//   x(n+1)   = x(n) + h v(n+1/2)
// Started with a half kick, v(1/2) = v(0) + h/2 a(0), which makes it second order (Stormer-
// Verlet); velocity-dependent forces see v(n-1/2), as in CORDIS. When the step changes, the kick
// spans the two half steps, (h_old + h_new)/2. Whether the half kick was applied and the last
// step are kept in the State (SchemeHistory): a copy of the State continues exactly.
#include "integrators.hpp"

namespace maille {

namespace {

// The step itself: KickDriftScheme's, with the kick below.
class Leapfrog final : public KickDriftScheme {
 public:
  std::string_view name() const override { return "leapfrog"; }

  std::optional<KickDrift> kick_drift_step(const State& s, Real h) const override {
    const Real kick =
        primed_here(s) ? Real(0.5) * (static_cast<Real>(s.history.last_h) + h) : Real(0.5) * h;
    return KickDrift{kick, h, {std::string(name()), true, static_cast<double>(h)}};
  }

  VelocityTime velocity_time(const State& s) const override {
    return primed_here(s) ? VelocityTime::half_step : VelocityTime::synchronous;
  }

  void synchronized_velocity(const Model& m, const State& s, Real h,
                             std::span<Vec3> out) const override {
    const auto v = s.v();
    const auto f = s.f();
    const Real half = primed_here(s) ? Real(0.5) * h : Real(0);
    for (std::size_t i = 0; i < out.size(); ++i)
      out[i] = v[i] + f[i] * (m.points.inv_mass[i] * half);
  }

  // The increment: KickDriftScheme's. In steady state the same recurrence as symplectic Euler
  // (the half-kick start only shifts where velocities are sampled).

 private:
  bool primed_here(const State& s) const { return s.history.primed && s.history.scheme == name(); }
};

}  // namespace

std::unique_ptr<Integrator> make_leapfrog() {
  return std::make_unique<Leapfrog>();
}

}  // namespace maille
