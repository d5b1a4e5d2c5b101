#include <algorithm>
#include <cmath>
#include <complex>
#include <cstdint>
#include <limits>

#include "../core/point_update.hpp"
#include "integrators.hpp"

namespace maille {

void Integrator::synchronized_velocity(const Model&, const State& s, Real,
                                       std::span<Vec3> out) const {
  const auto v = s.v();
  for (std::size_t i = 0; i < out.size(); ++i) out[i] = v[i];
}

bool is_stable(const Amplification& n) {
  const std::complex<double> tr = n[0][0] + n[1][1];
  const std::complex<double> det = n[0][0] * n[1][1] - n[0][1] * n[1][0];
  const std::complex<double> root = std::sqrt(tr * tr / 4.0 - det);
  constexpr double eps = std::numeric_limits<double>::epsilon();
  for (const std::complex<double> mu : {tr / 2.0 + root, tr / 2.0 - root}) {
    // |1 + mu|^2 - 1 = 2 Re mu + |mu|^2, computed without forming 1 + mu; rounding in mu is
    // about eps |mu|, hence the allowance.
    if (2 * mu.real() + std::norm(mu) > 8 * eps * std::abs(mu)) return false;
  }
  return true;
}

Amplification multiply(const Amplification& a, const Amplification& b) {
  Amplification r{};
  for (int i = 0; i < 2; ++i)
    for (int j = 0; j < 2; ++j) r[i][j] = a[i][0] * b[0][j] + a[i][1] * b[1][j];
  return r;
}

Amplification compose(const Amplification& a, const Amplification& b) {
  Amplification r = multiply(a, b);
  for (int i = 0; i < 2; ++i)
    for (int j = 0; j < 2; ++j) r[i][j] += a[i][j] + b[i][j];
  return r;
}

Amplification kick_drift_increment(double h, double w2, double c) {
  return {{{-h * h * w2, h * (1 - h * c)}, {-h * w2, -h * c}}};
}

// The stable steps form an interval [0, h*] for every built-in scheme: scan doubling steps
// from far below 1/omega until one is unstable, then bisect. Undamped symplectic schemes sit
// exactly on the unit circle (stable up to rounding); explicit Euler without damping grows by
// |mu|^2 per step, which is unstable at any step.
//
// Every loop is bounded. omega^2 or a damping rate that overflowed to infinity (a 1e-320 kg
// mass, a 1e308 N/m spring) is taken as 1e300, so the answer stays that of a very stiff link
// (about 1e-150 s for explicit schemes, +inf for implicit Euler); NaN gives 0. A step whose
// increment is not finite counts as unstable; the scan gives up (+inf) at 1e9 times the
// natural time scale.
Real Integrator::stable_step(Real w2, Real c) const {
  if (!(w2 >= 0) || !(c >= 0)) return 0;  // NaN or negative: nothing is known to be stable
  const double w2d = std::min(double(w2), 1e300), cd = std::min(double(c), 1e300);
  auto stable = [&](double h) {
    const Amplification n = increment(h, w2d, cd);
    for (const auto& row : n)
      for (const auto& e : row)
        if (!std::isfinite(e)) return false;
    return is_stable(n);
  };
  const double scale = 1 / (std::sqrt(w2d) + cd + 1e-300);
  double lo = 1e-6 * scale;
  if (!(lo > 0) || !std::isfinite(lo) || !stable(lo)) return 0;
  double hi = lo;
  for (int doublings = 0; stable(hi); ++doublings) {
    lo = hi;
    hi *= 2;
    if (hi > 1e9 * scale || doublings > 64 || !std::isfinite(hi))
      return std::numeric_limits<Real>::infinity();
  }
  for (int i = 0; i < 200 && hi - lo > 1e-15 * hi; ++i) {
    const double mid = 0.5 * (lo + hi);
    (stable(mid) ? lo : hi) = mid;
  }
  return static_cast<Real>(lo);
}

void kick_drift(const Model& m, State& s, Real kick, Real drift, int threads) {
  const Real* inv_mass = m.points.inv_mass.data();
  const Vec3* f = s.f().data();
  Vec3* v = s.v().data();
  Vec3* x = s.x().data();
  const auto n = static_cast<std::int64_t>(s.size());
  // One thread: no parallel construct at all. `omp parallel ... if (false)` still starts a team
  // of one, a futex system call per step (a tenth of a 30-bead string's step at audio rate).
  if (threads <= 1) {
    for (std::int64_t i = 0; i < n; ++i)
      point_update::kick_drift(x[i], v[i], f[i], inv_mass[i], kick, drift);
    return;
  }
#pragma omp parallel for schedule(static) num_threads(threads)
  for (std::int64_t i = 0; i < n; ++i)
    point_update::kick_drift(x[i], v[i], f[i], inv_mass[i], kick, drift);
}

const IntegratorRegistry& IntegratorRegistry::builtin() {
  static const IntegratorRegistry registry = [] {
    IntegratorRegistry r;
    auto plain = [](std::unique_ptr<Integrator> (*make)()) {
      return [make](const ImplicitSettings&) { return make(); };
    };
    r.add({"leapfrog", "CORDIS leapfrog, half-step velocities, 2nd order (default)",
           plain(make_leapfrog)});
    r.add({"symplectic_euler", "kick-drift Euler, 1st order, symplectic",
           plain(make_symplectic_euler)});
    r.add({"explicit_euler", "forward Euler, 1st order, unstable without damping",
           plain(make_explicit_euler)});
    r.add({"velocity_verlet", "kick-drift-kick, full-step velocities, 2nd order, 2 force passes",
           plain(make_velocity_verlet)});
    r.add({"rk4", "classical Runge-Kutta, 4th order, 4 force passes", plain(make_rk4)});
    r.add({std::string(kImplicitEuler),
           "backward Euler (Baraff-Witkin), 1st order, unconditionally stable",
           make_implicit_euler});
    return r;
  }();
  return registry;
}

}  // namespace maille
