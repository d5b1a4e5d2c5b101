#include <stdexcept>
#include <string>

#include "maille/link_loops.hpp"
#include "stages.hpp"

namespace maille::stages {

// One parallel region for all pools: each pool splits its colour groups among the threads
// (orphaned `omp for` inside LinkPool::accumulate), so the region is opened once per step.
LinkCounters link_forces(const Model& m, State& s, int threads) {
  LinkCounters counters;
  const Vec3* x = s.x().data();
  const Vec3* v = s.v().data();
  Vec3* f = s.f().data();
  const auto pools = m.links.pools();
  // A pool edited since prepare() would silently skip its links: refuse (programmer error),
  // before the parallel region where an exception cannot cross.
  for (const auto& pool : pools) pool->reserve_threads(threads);  // row buffers, once
  for (const auto& pool : pools)
    if (!pool->prepared())
      throw std::logic_error("link pool '" + std::string(pool->keyword()) +
                             "' changed since prepare(): edit models through "
                             "Simulator::edit_model");
  if (threads > 1) {
#pragma omp parallel num_threads(threads)
    for (const auto& pool : pools) accumulate_forces(*pool, x, v, f, counters);
  } else {
    for (const auto& pool : pools) accumulate_forces(*pool, x, v, f, counters);
  }
  return counters;
}

}  // namespace maille::stages
