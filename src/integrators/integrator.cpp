#include <cmath>
#include <cstdint>
#include <limits>

#include "integrators.hpp"

namespace maille {

void Integrator::synchronized_velocity(const Model&, const State& s, Real,
                                       std::span<Vec3> out) const {
  const auto v = s.v();
  for (std::size_t i = 0; i < out.size(); ++i) out[i] = v[i];
}

Real kick_drift_stable_step(Real omega2, Real c) {
  if (omega2 <= 0) return c > 0 ? Real(2) / c : std::numeric_limits<Real>::infinity();
  return (std::sqrt(c * c + 4 * omega2) - c) / omega2;
}

void kick_drift(const Model& m, State& s, Real kick, Real drift, int threads) {
  const Real* inv_mass = m.points.inv_mass.data();
  const Vec3* f = s.f().data();
  Vec3* v = s.v().data();
  Vec3* x = s.x().data();
  const auto n = static_cast<std::int64_t>(s.size());
#pragma omp parallel for schedule(static) num_threads(threads) if (threads > 1)
  for (std::int64_t i = 0; i < n; ++i) {
    const Real w = inv_mass[i];
    const Real moves = w > 0 ? drift : Real(0);
    v[i] += f[i] * (w * kick);
    x[i] += v[i] * moves;
  }
}

const IntegratorRegistry& IntegratorRegistry::builtin() {
  static const IntegratorRegistry registry = [] {
    IntegratorRegistry r;
    r.add(
        {"leapfrog", "CORDIS leapfrog, half-step velocities, 2nd order (default)", make_leapfrog});
    r.add({"symplectic_euler", "kick-drift Euler, 1st order, symplectic", make_symplectic_euler});
    return r;
  }();
  return registry;
}

const IntegratorRegistry::Entry* IntegratorRegistry::find(std::string_view name) const {
  for (const auto& e : entries_)
    if (e.name == name) return &e;
  return nullptr;
}

std::string IntegratorRegistry::names() const {
  std::string s;
  for (const auto& e : entries_) s += (s.empty() ? "" : ", ") + e.name;
  return s;
}

}  // namespace maille
