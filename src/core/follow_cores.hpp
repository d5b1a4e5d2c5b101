// The default thread count follows the free cores during a run, not only at its start (issue
// 24): a core that another program takes after the start made every barrier wait for a
// descheduled thread, and one that frees was left unused. Private to the core
// (simulator_threads.cpp).
#pragma once

#include <array>
#include <vector>

namespace maille::detail {

// The simulator's default answer to "how many cores are free now?", asked between steps every
// Simulator::CoreSampling::interval. Each call takes one sample of the other tasks runnable
// now: runnable_tasks() (free_cores.hpp) less this thread and less this process's OpenMP
// workers that are runnable (spinning at a barrier or working, they are ours, not another
// program's). It answers from the last kWindow samples, `cores` less the fewest other tasks
// among them (at least 1): a task runnable in every sample holds a core, one seen in some only
// is passing, as at the start (free_cores). Until kWindow samples are in, and when /proc
// cannot be read, it answers `start`. Allocates nothing after its first call.
class FreeCoreSampler {
 public:
  static constexpr int kWindow = 4;
  FreeCoreSampler(int cores, int start) : cores_(cores), start_(start) {}
  int operator()();

 private:
  // This thread's OpenMP pool (the thread ids of a team of `cores_`, this thread left out):
  // found again when another thread asks (a pool belongs to the thread that starts teams).
  void find_workers();
  int runnable_workers() const;

  int cores_, start_;
  std::array<int, kWindow> others_{};  // the last samples, a ring
  int samples_ = 0;
  std::vector<int> workers_;
  long asker_ = -1;
};

}  // namespace maille::detail
