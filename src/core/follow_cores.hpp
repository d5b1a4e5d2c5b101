// The default thread count follows the free cores during a run, not only at its start (issue
// 24): a core that another program takes after the start made every barrier wait for a
// descheduled thread, and one that frees was left unused. Private to the core
// (simulator_threads.cpp).
#pragma once

#include <array>
#include <cstdint>
#include <functional>
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

// The default thread count, chosen before each step: the cores free (asked every `interval`),
// and among 1 and that many threads the faster, measured. The rule "one thread below 4096
// points, else the free cores" guessed the work from the points; it missed small scenes whose
// points cost much (cloth_wringing, 384 points in self-collision, took 0.75 of one thread's
// time on two, idle) and large ones a loaded machine slows. So a trial runs `trial_steps` steps on
// one thread, then as many on the free cores (the first step of each discarded: waking threads,
// cold caches), times each step from one call to the next, and keeps the more threads only when
// their fastest step takes at most kGain of one thread's. A trial runs at the first step, when
// the free count changes, and every `retrial` ns (the work changes: a cloth falls into contact).
// When one core is free, one thread, without a trial. trial_steps = 0: the free cores, as told.
// Results do not depend on the choice (every pass sums in an order set by the model).
class ThreadChooser {
 public:
  static constexpr double kGain = 0.9;
  struct Settings {
    int cores = 1;                    // those OpenMP may use
    std::int64_t interval = 0;        // ns between two questions to free_cores
    int trial_steps = 6;              // timed steps per thread count in a trial
    std::int64_t retrial = 0;         // ns between two trials at the same free count
    std::function<int()> free_cores;  // the cores free now
  };
  ThreadChooser(Settings s, int start) : s_(std::move(s)), threads_(start) {}
  // The thread count for the step about to run; `now` in ns (steady clock).
  int before_step(std::int64_t now);

 private:
  void start_trial(std::int64_t now);

  Settings s_;
  int threads_;
  int free_ = 0;                    // the last answer (0: not asked yet)
  std::int64_t next_question_ = 0;  // ns
  std::int64_t next_trial_ = 0;     // ns
  int arm_ = -1;                    // the trial's count being timed: 0 one thread, 1 free_; -1 none
  int left_ = 0;                    // steps left in this arm, the discarded one included
  std::int64_t last_ = 0;           // when the previous step started
  std::array<std::int64_t, 2> best_{};  // the fastest step of each arm, ns
};

}  // namespace maille::detail
