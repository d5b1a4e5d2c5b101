// Cheap finiteness checks over point arrays, for the simulator's health stage.
#pragma once

#include <cmath>
#include <span>

#include "maille/vec3.hpp"

namespace maille {

// One vectorised pass: NaN and infinity survive "* 0", finite values vanish.
inline bool all_finite(std::span<const Vec3> a) {
  const Real* p = &a.data()->x;
  const std::size_t n = 3 * a.size();
  Real sum = 0;
#pragma omp simd reduction(+ : sum)
  for (std::size_t i = 0; i < n; ++i) sum += p[i] * 0;
  return std::isfinite(sum);
}

}  // namespace maille
