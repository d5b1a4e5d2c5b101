// The per-thread lists of the dynamically scheduled contact passes (src/collision/
// thread_lists.hpp). Which thread finds which pairs is up to OpenMP's dynamic schedule, so up
// to the load on the machine: under load one thread may find every pair of a pass, long after
// the first steps sized the lists (physics.Allocation.NoneInGroupContactsAfterTheFirstSteps
// failed so, in its sinks, on a loaded machine). Here the worst split is made on cue: after a
// pass on two threads, each sink in turn becomes thread 0's and a pass on one thread puts every
// pair in it; its buffer must not move (no reallocation), whatever each thread found before.
#include <gtest/gtest.h>

#include <functional>
#include <random>
#include <utility>
#include <vector>

#include "collision/self/broad_phase.hpp"
#include "collision/thread_lists.hpp"

namespace {

using namespace maille;
using namespace maille::collision;

using Pass = std::function<void(const Query&, std::vector<Sink>&, int)>;

void expect_no_sink_grows_under_any_split(const char* what, const Pass& pass) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<Real> u(0, 1);
  std::vector<Vec3> x(1500);
  for (auto& p : x) p = {u(rng), u(rng), u(rng)};
  Query q;
  q.x = x.data();
  q.n = std::uint32_t(x.size());
  q.r = Real(0.08);  // about 2,000 pairs
  std::vector<Sink> sinks(2);
  auto run = [&](int threads) {
    for (auto& s : sinks) s.clear();
    pass(q, sinks, threads);
    std::size_t entries = 0;
    for (const auto& s : sinks) entries += s.pairs.size();
    return entries;
  };
  const std::size_t entries = run(2);
  ASSERT_GT(entries, 4000u) << what;
  for (std::size_t k = 0; k < sinks.size(); ++k) {
    std::swap(sinks[0], sinks[k]);  // sink k is thread 0's now: alone, it finds every pair
    const std::uint32_t* before = sinks[0].pairs.data();
    EXPECT_EQ(run(1), entries) << what;
    EXPECT_EQ(sinks[0].pairs.data(), before) << what << ": sink " << k << " grew";
  }
}

TEST(ThreadLists, NoSinkGrowsWhenOneThreadFindsEveryPair) {
  UniformGrid uniform;
  HashedGrid hashed;
  Octree octree;
  expect_no_sink_grows_under_any_split(
      "brute", [](const Query& q, auto& s, int t) { brute_pairs(q, s, t); });
  expect_no_sink_grows_under_any_split(
      "uniform", [&](const Query& q, auto& s, int t) { uniform.find(q, q.r, s, t); });
  expect_no_sink_grows_under_any_split(
      "hashed", [&](const Query& q, auto& s, int t) { hashed.find(q, q.r, s, t); });
  expect_no_sink_grows_under_any_split(
      "hierarchical", [&](const Query& q, auto& s, int t) { octree.find(q, s, t); });
}

// Each list's room: the whole output rounded up to a power of two (a growing vector's own
// rule), within the cap; scratch lists: the largest any has had.
TEST(ThreadLists, RoomIsTheWholeOutputWithinTheCap) {
  std::vector<std::vector<int>> lists(3);
  lists[0].assign(5, 0);
  lists[1].assign(1, 0);
  room_for_any_split(lists, 1000);
  for (const auto& l : lists) EXPECT_GE(l.capacity(), 8u);
  std::vector<std::vector<int>> capped(2);
  capped[0].assign(100, 0);
  room_for_any_split(capped, 50);
  EXPECT_LT(capped[1].capacity(), 100u);
  EXPECT_GE(capped[1].capacity(), 50u);
  std::vector<std::vector<int>> scratch(2);
  scratch[1].reserve(40);
  room_for_any_item(scratch);
  EXPECT_GE(scratch[0].capacity(), 40u);
}

}  // namespace
