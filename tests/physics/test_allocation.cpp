// No allocation in the step: after the first step (which sizes scratch buffers), stepping a
// flag allocates nothing, with leapfrog and with implicit Euler (matrix-free CG), on one thread
// and two. Counted by replacing the global operator new in this test binary.
#include <gtest/gtest.h>

#include <atomic>
#include <cstdlib>
#include <new>

#include "maille/builders.hpp"
#include "maille/scene.hpp"
#include "test_support.hpp"

namespace {
std::atomic<bool> g_counting{false};
std::atomic<long> g_allocations{0};
}  // namespace

// GCC 12 with -fsanitize=address (the asan preset) inlines these into their callers and then
// warns that free() releases memory from operator new: a false positive for a replacement pair.
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wmismatched-new-delete"
void* operator new(std::size_t n) {
  if (g_counting.load(std::memory_order_relaxed)) g_allocations.fetch_add(1);
  if (void* p = std::malloc(n ? n : 1)) return p;
  throw std::bad_alloc();
}
// The nothrow form too (std::stable_sort's temporary buffer uses it): left to the library, its
// memory would come back through the operator delete below, into free() (ASan: alloc-dealloc
// mismatch). The array forms call these by default.
void* operator new(std::size_t n, const std::nothrow_t&) noexcept {
  if (g_counting.load(std::memory_order_relaxed)) g_allocations.fetch_add(1);
  return std::malloc(n ? n : 1);
}
void operator delete(void* p) noexcept {
  std::free(p);
}
void operator delete(void* p, std::size_t) noexcept {
  std::free(p);
}
#pragma GCC diagnostic pop

namespace maille {
namespace {

long allocations_in_steps(const char* scheme, int threads, const char* solver = "matrix_free") {
  Model m;
  FlagParams p;
  p.nx = 64;  // 4096 points: large enough that two threads are used when asked
  p.ny = 64;
  build_flag(m, p, "flag");
  m.fields.wind.velocity = {5, 0, 1};
  m.fields.wind.turbulence = 0.3;
  SimulationSettings s =
      test::settings(scheme == std::string("implicit_euler") ? 2e-3 : 1e-4, scheme);
  s.threads = threads;
  s.implicit.solver = *parse_name<ImplicitSolver>(solver);
  s.sample_every = 5;
  s.publish_every = 5;
  Simulator sim(std::move(m), s);
  sim.on_publish([](const Snapshot&) {});
  sim.run_steps(5);  // sizes the scratch buffers and the snapshot
  g_allocations = 0;
  g_counting = true;
  sim.run_steps(20);
  g_counting = false;
  return g_allocations.load();
}

TEST(Allocation, CounterSeesAllocations) {  // the instrument works
  g_allocations = 0;
  g_counting = true;
  auto* v = new std::vector<int>(1000);
  g_counting = false;
  delete v;
  EXPECT_GE(g_allocations.load(), 2);
}

TEST(Allocation, NoneInTheStepAfterTheFirst) {
  for (const char* scheme : {"leapfrog", "implicit_euler", "rk4", "velocity_verlet"})
    for (int threads : {1, 2})
      EXPECT_EQ(allocations_in_steps(scheme, threads), 0)
          << scheme << " on " << threads << " threads";
  for (int threads : {1, 2})
    EXPECT_EQ(allocations_in_steps("implicit_euler", threads, "vbd"), 0)
        << "implicit_euler (vbd) on " << threads << " threads";
}

}  // namespace
}  // namespace maille

namespace maille {
namespace {

// Contacts between groups (the broad-phase stage: grid, sinks and rows keep their capacity):
// the jelly cube starting inside its floor's reach, thrown up by its contacts, allocates
// nothing once the first steps have sized the buffers (contacts still act while counted).
TEST(Allocation, NoneInGroupContactsAfterTheFirstSteps) {
  auto loaded = load_scene(std::string(MAILLE_SOURCE_DIR "/examples/jelly_cube_bounce.toml"),
                           std::vector<std::string>{"lattice[0].origin=[-0.25,0.06,-0.25]"});
  ASSERT_TRUE(loaded) << loaded.error().to_string();
  for (int threads : {1, 2}) {
    SimulationSettings s = loaded->settings;
    s.threads = threads;
    Simulator sim(loaded->model, s);
    sim.run_steps(30);  // the first contacts size the buffers
    g_allocations = 0;
    g_counting = true;
    sim.run_steps(20);
    g_counting = false;
    EXPECT_EQ(g_allocations.load(), 0) << threads << " threads";
    std::uint64_t active = 0;
    for (const auto& c : sim.profile().counters())
      if (c.name == "active_conditional_links") active = c.last;
    EXPECT_GT(active, 0u) << "the cube left the floor: nothing was measured";
  }
}

}  // namespace
}  // namespace maille
