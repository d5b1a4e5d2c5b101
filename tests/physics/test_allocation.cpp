// No allocation in the step: after the first steps (which size scratch buffers), stepping a
// flag allocates nothing, with leapfrog and with implicit Euler (matrix-free CG), on one thread
// and two; and so does every scheme (every implicit solver) on a scene with every stage kind
// on: wind, a drive, [[contact]] links, a geometric contact, self-collision (points and
// triangles), obstacles by every method (facets with the single-pass schemes that take them);
// and contacts still allocate nothing when the thread count falls from two to one.
// Counted by replacing the global operator new in this test binary.
#include <gtest/gtest.h>

#include <atomic>
#include <cstdlib>
#include <new>

#include "maille/builders.hpp"
#include "maille/live.hpp"
#include "maille/scene.hpp"
#include "ring_player.hpp"
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

long allocations_in_steps(const char* scheme, int threads, const char* solver = "matrix_free",
                          bool wind = true) {
  Model m;
  FlagParams p;
  p.nx = 64;  // 4096 points: large enough that two threads are used when asked
  p.ny = 64;
  build_flag(m, p, "flag");
  if (wind) {
    m.fields.wind.velocity = {5, 0, 1};
    m.fields.wind.turbulence = 0.3;
  }
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
  // Without wind a lone flag takes the fused grid step (simulator_fused.cpp) four steps in five
  // (the fifth samples energies): its row buffers are sized once.
  for (const char* scheme : {"leapfrog", "symplectic_euler"})
    for (int threads : {1, 2})
      EXPECT_EQ(allocations_in_steps(scheme, threads, "matrix_free", false), 0)
          << scheme << " (fused grid step) on " << threads << " threads";
  for (const char* solver : {"eigen", "vbd"})
    for (int threads : {1, 2})
      EXPECT_EQ(allocations_in_steps("implicit_euler", threads, solver), 0)
          << "implicit_euler (" << solver << ") on " << threads << " threads";
}

// The default thread count following the cores (simulator_threads.cpp): the thread count
// changes between steps (the cores are told busy and free in turn), and nothing allocates once
// both counts have run; nor does the default question (/proc read before every step, and the
// timed trials of 1 and 2 threads).
TEST(Allocation, NoneWhileTheThreadsFollowTheCores) {
  for (const char* scheme : {"leapfrog", "implicit_euler", "proc"}) {
    Model m;
    FlagParams p;
    p.nx = 64;  // 4096 points: the default thread count follows the cores
    p.ny = 64;
    build_flag(m, p, "flag");
    const bool proc = scheme == std::string("proc");
    SimulationSettings s = test::settings(scheme == std::string("implicit_euler") ? 2e-3 : 1e-4,
                                          proc ? "leapfrog" : scheme);
    s.threads = 0;
    Simulator sim(std::move(m), s);
    if (proc)
      sim.set_core_sampling({nullptr, 0.0});
    else
      sim.set_core_sampling({[asked = 0]() mutable { return asked++ % 2 + 1; }, 0.0, 0});
    sim.run_steps(6);
    g_allocations = 0;
    g_counting = true;
    sim.run_steps(10);
    g_counting = false;
    EXPECT_EQ(g_allocations.load(), 0) << scheme;
  }
}

// Every stage kind at once; `extra` adds tables (the facet obstacle, the triangle primitive).
std::string every_stage_scene(const std::string& extra) {
  return R"(
[fields]
gravity = [0.0, -9.81, 0.0]
air_drag = 0.1
[fields.wind]
velocity = [3.0, 0.0, 1.0]
turbulence = 0.3
[[flag]]
name = "cloth"
origin = [0.0, 1.0, 0.0]
width = 0.6
height = 0.4
resolution = [16, 12]
mass = 0.1
stiffness = 200.0
shear_stiffness = 60.0
bending_stiffness = 5.0
damping = 0.02
fixed = "pole"
[flag.drive]
path = "sine"
amplitude = [0.0, 0.0, 0.05]
frequency = 2.0
[[rope]]
name = "rope"
start = [0.3, 0.9, 0.02]
end = [0.3, 0.5, 0.02]
points = 8
mass = 0.05
stiffness = 100.0
damping = 0.01
fixed = "start"
[[contact]]
between = ["cloth", "rope"]
stiffness = 100.0
threshold = 0.03
[[geometric_point]]
name = "post"
position = [0.25, 0.75, 0.0]
scale = [0.08, 0.08, 0.08]
[[link]]
kind = "geometric_contact"
a = "post"
b = "cloth"
stiffness = 100.0
[[obstacle]]
name = "ball"
method = "geometric"
position = [0.45, 0.8, 0.0]
scale = [0.08, 0.08, 0.08]
stiffness = 300.0
collides_with = ["cloth", "rope"]
[[obstacle]]
name = "pebble"
method = "conditional"
position = [0.15, 0.7, 0.0]
scale = [0.06, 0.06, 0.06]
resolution = 16
threshold = 0.02
stiffness = 300.0
collides_with = ["cloth"]
)" + extra;
}

long allocations_with_every_stage(const std::string& scheme, const std::string& solver,
                                  const std::string& extra, int threads) {
  static const LinkKindRegistry kinds = LinkKindRegistry::with_builtins();
  static const StageRegistry stages = StageRegistry::with_builtins();
  auto scene = parse_scene(every_stage_scene(extra), "every_stage", kinds, stages);
  if (!scene) {
    ADD_FAILURE() << scene.error().to_string();
    return -1;
  }
  SimulationSettings s = test::settings(scheme == "implicit_euler" ? 1e-3 : 1e-4, scheme.c_str());
  s.threads = threads;
  s.implicit.solver = *parse_name<ImplicitSolver>(solver);
  s.sample_every = 5;
  s.publish_every = 5;
  Simulator sim(std::move(scene->model), s);
  sim.on_publish([](const Snapshot&) {});
  if (!sim.run_steps(30)) {  // sizes the scratch buffers, the contacts' and the snapshot
    ADD_FAILURE() << sim.blow_up()->message;
    return -1;
  }
  g_allocations = 0;
  g_counting = true;
  sim.run_steps(20);
  g_counting = false;
  return g_allocations.load();
}

TEST(Allocation, NoneInTheStepWithEveryStageKind) {
  const std::string self = "[self_collision]\ngroups = [\"cloth\"]\nradius = 0.02\n";
  const std::string triangles = self + "primitive = \"triangles\"\n";
  const std::string facets =
      "[[obstacle]]\nname = \"box\"\nmethod = \"facets\"\nshape = \"cube\"\n"
      "position = [0.35, 0.6, 0.1]\nscale = [0.06, 0.06, 0.06]\ncollides_with = [\"cloth\"]\n";
  struct Case {
    std::string scheme, solver, extra;
  };
  std::vector<Case> cases;
  for (const char* scheme : {"leapfrog", "symplectic_euler", "explicit_euler"})
    for (const std::string& sc : {self, triangles}) cases.push_back({scheme, "", sc + facets});
  for (const char* scheme : {"velocity_verlet", "rk4"})
    for (const std::string& sc : {self, triangles}) cases.push_back({scheme, "", sc});
  // Implicit Euler runs facets after its solve. eigen is the allocating reference (Eigen's CG
  // allocates its vectors on every solve, and the contacts rebuild its pattern): not here.
  for (const char* solver : {"matrix_free", "vbd"})
    for (const std::string& sc : {self, triangles})
      cases.push_back({"implicit_euler", solver, sc + facets});
  for (const Case& c : cases)
    for (int threads : {1, 2})
      EXPECT_EQ(allocations_with_every_stage(c.scheme, c.solver.empty() ? "matrix_free" : c.solver,
                                             c.extra, threads),
                0)
          << c.scheme << (c.solver.empty() ? "" : " (" + c.solver + ")") << " on " << threads
          << " threads, "
          << (c.extra.find("triangles") != std::string::npos ? "triangles" : "points")
          << (c.extra.find("facets") != std::string::npos ? ", facets" : "");
}

// The viewer's audio path (apps/play/ring_player.hpp): the device's callback (RingPlayer::
// process, both layouts) copies from the ring through a gain ramp, and fills with silence and
// counts an xrun when the ring runs dry; the physics thread's producer (fill) renders blocks
// into the ring. Neither allocates once the first block has run.
TEST(Allocation, NoneInTheViewersRingAndCallback) {
  const std::string drum = std::string(MAILLE_SOURCE_DIR) + "/examples/play_drum.toml";
  const std::vector<std::string> sets{"membrane[0].rings=6", "listen[0].point=skin:45",
                                      "control[0].excite.point=skin:35"};
  auto scene = load_scene(drum, sets);
  ASSERT_TRUE(scene) << scene.error().to_string();
  SimulationSettings s = scene->settings;
  s.threads = 1;
  Simulator sim(scene->model, s);
  scene->audio.controls.resize(1);  // the strike alone (the tension's glides: the test above)
  audio::LiveSource src(sim, scene->audio, 48000, {}, 64);
  play::RingPlayer player(1, 48000, 2 * 256 + 480, 64);
  play::ControlRings controls;
  std::vector<float> period(256), interleaved(256);
  float* out[] = {period.data()};
  player.fill(src, &controls);  // the first blocks size the step's scratch buffers
  player.set_producing(true);
  g_allocations = 0;
  g_counting = true;
  for (int round = 0; round < 40; ++round) {
    if (round % 8 == 0) player.set_gain(0.5f + 0.1f * float(round % 3));  // ramps
    controls.osc.push({0, 0, 1.0f});                                      // strikes
    player.fill(src, &controls);
    player.process(out, 256);
    player.process_interleaved(interleaved.data(), 256);
  }
  for (int dry = 0; dry < 8; ++dry) player.process(out, 256);  // the ring runs dry: silence
  g_counting = false;
  EXPECT_EQ(g_allocations.load(), 0);
  EXPECT_GT(player.counters().underruns, 0u);
  EXPECT_EQ(period.back(), 0.0f);
  EXPECT_FALSE(src.blown_up());
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

namespace maille {
namespace {

// The default thread count falls from two to one (another program takes a core) while contacts
// act: nothing allocates in the steps on one thread, though thread 0 alone now finds every
// contact the two threads shared (each pass leaves every thread's list room for all of them:
// src/collision/thread_lists.hpp; unit.ThreadLists makes the worst split on cue). The cores
// are told: two free, then one.
long allocations_two_threads_then_one(Model model, SimulationSettings s, int first, int counted) {
  int free_cores = 2;
  s.threads = 0;
  Simulator sim(std::move(model), s);
  sim.set_core_sampling({[&free_cores] { return free_cores; }, 0.0, 0});
  if (!sim.follows_cores()) {
    ADD_FAILURE() << "one core: the thread count cannot change";
    return -1;
  }
  if (!sim.run_steps(first) || sim.threads() != 2) {
    ADD_FAILURE() << "the first steps did not run on two threads: "
                  << (sim.blow_up() ? sim.blow_up()->message : std::to_string(sim.threads()));
    return -1;
  }
  free_cores = 1;
  sim.run_steps(1);  // the switch to one thread itself
  g_allocations = 0;
  g_counting = true;
  sim.run_steps(counted);
  g_counting = false;
  EXPECT_EQ(sim.threads(), 1);
  return g_allocations.load();
}

// Two square sheets 1 cm apart, in contact all over and at rest (no gravity, no wind): every
// step finds the same contacts, about 5 per point, spread over the whole grid (every chunk of
// the dynamic schedule holds some). `contact` is the table that finds them.
std::string sheets_scene(const std::string& contact) {
  std::string s = R"(
[fields]
gravity = [0.0, 0.0, 0.0]
)";
  for (const auto& [name, z] : {std::pair{"a", "0.0"}, std::pair{"b", "0.01"}})
    s += std::string("[[flag]]\nname = \"") + name + "\"\norigin = [0.0, 0.0, " + z +
         "]\nwidth = 0.46\nheight = 0.46\nresolution = [24, 24]\nmass = 0.1\n"
         "stiffness = 200.0\nfixed = \"none\"\n";
  return s + contact;
}

TEST(Allocation, NoneWhenTheThreadsFallToOneWithContacts) {
  static const LinkKindRegistry kinds = LinkKindRegistry::with_builtins();
  static const StageRegistry stages = StageRegistry::with_builtins();
  const std::string self =
      "[self_collision]\ngroups = [\"a\", \"b\"]\nradius = 0.03\nstiffness = 1.0\n";
  const std::pair<const char*, std::string> cases[] = {
      {"group contacts",
       "[[contact]]\nbetween = [\"a\", \"b\"]\nstiffness = 1.0\nthreshold = 0.03\n"},
      {"self-collision, points", self},
      // Faces and edges: about 11 face and 3 edge contacts per point at once, whose dampers
      // summed at the default 0.5 N.s/m put 2e-5 s at the explicit limit (the sheets then ring
      // and their contacts never settle); 0.1 keeps them at rest.
      {"self-collision, triangles", self + "primitive = \"triangles\"\ndamping = 0.1\n"},
  };
  for (const auto& [what, contact] : cases) {
    auto scene = parse_scene(sheets_scene(contact), "sheets", kinds, stages);
    ASSERT_TRUE(scene) << scene.error().to_string();
    SimulationSettings s = test::settings(2e-5, "leapfrog");  // the sheets' springs: h < 6.6e-5 s
    EXPECT_EQ(allocations_two_threads_then_one(std::move(scene->model), s, 10, 10), 0) << what;
  }
}

// `maille play`'s audio path: the callback's work (LiveSource::control and render: control
// glides rewriting every link's stiffness, strikes, K steps per sample, the channels read)
// allocates nothing once the first block has run. The lock-free rings are checked to be so at
// compile time (live.hpp).
TEST(Allocation, NoneInTheLiveAudioPath) {
  const std::string drum = std::string(MAILLE_SOURCE_DIR) + "/examples/play_drum.toml";
  const std::vector<std::string> sets{"membrane[0].rings=6", "listen[0].point=skin:45",
                                      "control[0].excite.point=skin:35"};
  auto scene = load_scene(drum, sets);
  ASSERT_TRUE(scene) << scene.error().to_string();
  std::vector<audio::ParameterTable> tables(scene->audio.controls.size());
  auto t =
      build_parameter_table(drum, sets, scene->model, scene->settings, scene->audio.controls[1]);
  ASSERT_TRUE(t) << t.error().to_string();
  tables[1] = t.value();
  SimulationSettings s = scene->settings;
  s.threads = 1;
  s.publish_every = kNeverEvery;
  s.sample_every = kNeverEvery;
  Simulator sim(scene->model, s);
  audio::LiveSource src(sim, scene->audio, 48000, tables, 64);
  std::vector<float> out(64);
  src.control({0, 0, 1.0f});
  src.render(out.data(), 64);  // the first block sizes the step's scratch buffers
  g_allocations = 0;
  g_counting = true;
  for (int block = 0; block < 200; ++block) {
    if (block % 10 == 0) src.control({1, float(block % 30) / 30.0f, 0});  // glides
    if (block % 25 == 0) src.control({0, 0, 0.5f});                       // strikes
    src.render(out.data(), 64);
  }
  g_counting = false;
  EXPECT_EQ(g_allocations.load(), 0);
  EXPECT_FALSE(src.blown_up());
}

}  // namespace
}  // namespace maille
