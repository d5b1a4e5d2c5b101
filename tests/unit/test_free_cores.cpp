// The default thread count follows the cores actually free (src/core/free_cores.hpp): another
// runnable task in every sample takes a core; a task seen in some samples only is passing.
#include <gtest/gtest.h>

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

}  // namespace
}  // namespace maille::detail
