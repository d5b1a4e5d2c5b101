// What the large-step tests and bench/drape_quality measure of a cloth: its largest stretch.
// (Crossing triangle pairs: intersections.hpp.)
#pragma once

#include <algorithm>
#include <cstddef>

#include "maille/simulator.hpp"

namespace maille::test {

// The largest |x_b - x_a| / L0 - 1 over the model's spring-dampers (structural, shear, bending).
inline double largest_stretch(const Simulator& sim) {
  const auto* pool = sim.model().links.find("spring_damper");
  double worst = 0;
  for (std::size_t l = 0; pool && l < pool->size(); ++l) {
    const auto [a, b] = pool->ends(l);
    worst = std::max(worst, norm(sim.state().x()[b] - sim.state().x()[a]) / pool->param(l, 1) - 1);
  }
  return worst;
}

}  // namespace maille::test
