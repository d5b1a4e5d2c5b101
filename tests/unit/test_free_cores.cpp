// The default thread count follows the cores actually free (src/core/free_cores.hpp): another
// runnable task in every sample takes a core; a task seen in some samples only is passing.
#include <gtest/gtest.h>

#include <cstdint>
#include <functional>
#include <vector>

#include "core/follow_cores.hpp"
#include "core/free_cores.hpp"

namespace maille::detail {
namespace {

int free_of(int cores, std::vector<int> running) {
  return free_cores_from(cores, running);
}

TEST(FreeCores, OtherRunnableTasksTakeCores) {
  EXPECT_EQ(free_of(2, {1, 1, 1, 1, 1}), 2);  // only this thread: an idle machine
  EXPECT_EQ(free_of(2, {2, 2, 3, 2, 2}), 1);  // one busy core elsewhere
  EXPECT_EQ(free_of(2, {1, 2, 2, 2, 2}), 2);  // busy in some samples only: passing
  EXPECT_EQ(free_of(8, {4, 5, 4, 4, 6}), 5);
  EXPECT_EQ(free_of(2, {9, 8, 9, 9, 8}), 1);  // never below one
  EXPECT_EQ(free_of(4, {}), 4);               // nothing read: the core count
  EXPECT_EQ(free_of(1, {1}), 1);
}

TEST(FreeCores, NeverMoreThanTheCoresNorLessThanOne) {
  const int cores = free_cores(2);
  EXPECT_GE(cores, 1);
  EXPECT_LE(cores, 2);
}

// /proc/stat read without a stream (the simulator asks during a run): at least this thread.
TEST(FreeCores, RunnableTasksCountThisThread) {
  EXPECT_GE(runnable_tasks(), 1);
}

// During a run: the count at the start until the window is full, then within [1, cores].
TEST(FreeCores, SamplerStartsFromTheStartCount) {
  FreeCoreSampler sample(2, 2);
  for (int k = 1; k < FreeCoreSampler::kWindow; ++k) EXPECT_EQ(sample(), 2);
  const int free = sample();
  EXPECT_GE(free, 1);
  EXPECT_LE(free, 2);
}

// The measured choice, on a simulated clock: each step lasts `one` ns on one thread and `two`
// on two; returns the thread counts of `steps` steps.
std::vector<int> choose(ThreadChooser& chooser, std::int64_t& now, std::int64_t one,
                        std::int64_t two, int steps) {
  std::vector<int> out;
  for (int k = 0; k < steps; ++k) {
    const int threads = chooser.before_step(now);
    out.push_back(threads);
    now += threads == 1 ? one : two;
  }
  return out;
}

ThreadChooser::Settings chooser_settings(std::function<int()> free_cores) {
  ThreadChooser::Settings s;
  s.cores = 2;
  s.interval = 0;  // asked before every step
  s.trial_steps = 3;
  s.retrial = 10'000;
  s.free_cores = std::move(free_cores);
  return s;
}

TEST(ThreadChooser, KeepsTwoThreadsOnlyWhenTheyPay) {
  std::int64_t now = 0;
  ThreadChooser fast(chooser_settings([] { return 2; }), 1);
  // A trial: 1 + 3 steps on one thread, 1 + 3 on two, then two threads (60 < 0.9 x 100).
  EXPECT_EQ(choose(fast, now, 100, 60, 12), (std::vector<int>{1, 1, 1, 1, 2, 2, 2, 2, 2, 2, 2, 2}));
  now = 0;
  ThreadChooser slow(chooser_settings([] { return 2; }), 1);
  EXPECT_EQ(choose(slow, now, 100, 95, 10), (std::vector<int>{1, 1, 1, 1, 2, 2, 2, 2, 1, 1}));
}

TEST(ThreadChooser, OneFreeCoreIsOneThreadWithoutATrial) {
  std::int64_t now = 0;
  int free = 1;
  ThreadChooser chooser(chooser_settings([&free] { return free; }), 2);
  EXPECT_EQ(choose(chooser, now, 100, 60, 3), (std::vector<int>{1, 1, 1}));
  free = 2;  // the core frees: a new trial
  EXPECT_EQ(choose(chooser, now, 100, 60, 9), (std::vector<int>{1, 1, 1, 1, 2, 2, 2, 2, 2}));
  free = 1;  // taken again, mid-run: one thread at once
  EXPECT_EQ(choose(chooser, now, 100, 60, 2), (std::vector<int>{1, 1}));
}

TEST(ThreadChooser, TriesAgainAfterTheRetrialTime) {
  std::int64_t now = 0;
  ThreadChooser chooser(chooser_settings([] { return 2; }), 1);
  choose(chooser, now, 100, 95, 9);  // a trial, one thread kept
  now += 20'000;                     // past the retrial time: two threads pay now
  EXPECT_EQ(choose(chooser, now, 100, 50, 10), (std::vector<int>{1, 1, 1, 1, 2, 2, 2, 2, 2, 2}));
}

}  // namespace
}  // namespace maille::detail
