#include "maille/stability.hpp"

#include <cmath>
#include <limits>
#include <vector>

namespace maille {

StabilityEstimate estimate_stability(const Model& m, const Integrator& scheme,
                                     std::span<const Stage* const> stages) {
  const std::uint32_t n = m.points.size();
  std::vector<Real> k_row(n, 0), c_row(n, 0);
  // The stiffest kind per point, for the message: remember which pool added the most.
  std::vector<Real> best_k(n, 0);
  std::vector<int> best_pool(n, -1);
  const auto pools = m.links.pools();
  for (std::size_t p = 0; p < pools.size(); ++p) {
    std::vector<Real> k_here(n, 0), c_here(n, 0);
    pools[p]->stability_terms(m.points.inv_mass, k_here, c_here);
    for (std::uint32_t i = 0; i < n; ++i) {
      k_row[i] += k_here[i];
      c_row[i] += c_here[i];
      if (k_here[i] + c_here[i] > best_k[i]) {
        best_k[i] = k_here[i] + c_here[i];
        best_pool[i] = static_cast<int>(p);
      }
    }
  }
  std::vector<std::string> stage_name(n);
  for (const Stage* st : stages) {
    std::vector<Real> k_here(n, 0), c_here(n, 0);
    st->stability_terms(m.points.inv_mass, k_here, c_here);
    for (std::uint32_t i = 0; i < n; ++i) {
      k_row[i] += k_here[i];
      c_row[i] += c_here[i];
      if (k_here[i] + c_here[i] > best_k[i]) {
        best_k[i] = k_here[i] + c_here[i];
        best_pool[i] = -2;
        stage_name[i] = st->name();
      }
    }
  }
  StabilityEstimate est;
  est.max_step = std::numeric_limits<Real>::infinity();
  for (std::uint32_t i = 0; i < n; ++i) {
    const Real w = m.points.inv_mass[i];
    if (w == 0 || (k_row[i] == 0 && c_row[i] == 0)) continue;
    const Real omega2 = w * k_row[i], c = w * c_row[i];
    const Real h = scheme.stable_step(omega2, c);
    if (h < est.max_step) {
      est.max_step = h;
      est.point = i;
      est.omega = std::sqrt(omega2);
      est.damping_rate = c;
      est.link_kind = best_pool[i] >= 0    ? std::string(pools[best_pool[i]]->keyword())
                      : best_pool[i] == -2 ? stage_name[i]
                                           : "";
    }
  }
  return est;
}

}  // namespace maille
