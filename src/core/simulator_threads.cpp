// The default thread count follows the free cores during a run (Simulator::CoreSampling,
// issue 24). Asked between steps at a wall-clock interval, not every step: the default answer
// reads /proc (tens of microseconds), a step of a large scene takes about a millisecond.
#include <algorithm>
#include <chrono>

#include "follow_cores.hpp"
#include "maille/simulator.hpp"

namespace maille {

void Simulator::set_core_sampling(CoreSampling sampling) {
  core_sampling_ = std::move(sampling);
  next_core_check_ns_ = 0;  // asked before the next step
}

void Simulator::follow_cores() {
  const std::int64_t now = std::chrono::duration_cast<std::chrono::nanoseconds>(
                               std::chrono::steady_clock::now().time_since_epoch())
                               .count();
  if (now < next_core_check_ns_) return;
  next_core_check_ns_ = now + std::int64_t(core_sampling_.interval * 1e9);
  if (!core_sampling_.free_cores)
    core_sampling_.free_cores = detail::FreeCoreSampler(cores_, threads_);
  const int threads = std::clamp(core_sampling_.free_cores(), 1, cores_);
  if (threads != threads_) use_threads(threads);
}

// Every pass reads threads_ when it starts (stages through StageContext::threads); the scheme
// hands it on to its solvers.
void Simulator::use_threads(int threads) {
  threads_ = threads;
  integrator_->set_threads(threads);
}

}  // namespace maille
