// The default thread count follows the free cores and the work during a run
// (Simulator::CoreSampling). The cores are asked between steps at a wall-clock
// interval, not every step: the default answer reads /proc (about 60 us on the 2-core
// development machine), a step can take a few.
#include <algorithm>
#include <chrono>

#include "follow_cores.hpp"
#include "maille/simulator.hpp"
#include "maille/threads.hpp"

namespace maille {

void Simulator::set_core_sampling(CoreSampling sampling) {
  core_sampling_ = std::move(sampling);
  chooser_.reset();  // asked before the next step
}

void Simulator::follow_cores() {
  const std::int64_t now = std::chrono::duration_cast<std::chrono::nanoseconds>(
                               std::chrono::steady_clock::now().time_since_epoch())
                               .count();
  if (!chooser_) {
    detail::ThreadChooser::Settings s;
    s.cores = cores_;
    s.interval = std::int64_t(core_sampling_.interval * 1e9);
    s.trial_steps = core_sampling_.trial_steps;
    s.retrial = std::int64_t(core_sampling_.retrial * 1e9);
    s.free_cores = core_sampling_.free_cores ? core_sampling_.free_cores
                                             : detail::FreeCoreSampler(cores_, free_at_start_);
    chooser_ = std::make_unique<detail::ThreadChooser>(std::move(s), threads_);
    // The pools' per-thread buffers sized for every count the chooser may pick: it may first try
    // more threads many steps into a run (an idle machine's timed trial), and the step must not
    // allocate then (physics.Allocation.NoneWhileTheThreadsFollowTheCores failed 4 of 6 runs
    // on the idle 2-core machine: the structured kernel's rows reserved at the first 2-thread
    // step).
    for (const auto& pool : model_.links.pools()) pool->reserve_threads(cores_);
  }
  const int threads = chooser_->before_step(now);
  if (threads != threads_) use_threads(threads);
}

// Every pass reads threads_ when it starts (stages through StageContext::threads); the scheme
// hands it on to its solvers.
void Simulator::use_threads(int threads) {
  threads_ = usable_threads(threads);
  note_teams(threads_);
  integrator_->set_threads(threads_);
}

// In a child forked after teams ran (threads.hpp), one thread from now on: a team would wait
// for ever for threads that stayed in the parent.
void Simulator::keep_to_usable_threads() {
  if (!forked_after_teams()) return;
  follows_cores_ = false;
  if (threads_ > 1) use_threads(1);
}

}  // namespace maille
