// The default thread count follows the free cores during a run (Simulator::CoreSampling): a
// core that becomes busy, then free again, changes the thread count between steps, and the
// trajectory stays bit for bit that of a fixed thread count, with every stage kind on and every
// solver of implicit Euler. The cores are simulated: the test answers "how many are free?".
#include <gtest/gtest.h>

#ifdef _OPENMP
#include <omp.h>
#endif

#include <set>
#include <string>

#include "maille/scene.hpp"
#include "test_support.hpp"

namespace maille {
namespace {

// A 64 x 64 cloth (4,096 points: the default thread count follows the cores) on a pole in the
// wind, and `extra`. Heavy (10 kg), so that the steps below stay far within stability.
Model large_scene(const std::string& extra) {
  static const LinkKindRegistry kinds = LinkKindRegistry::with_builtins();
  static const StageRegistry stages = StageRegistry::with_builtins();
  const std::string text = R"(
[fields]
air_drag = 0.1
[fields.wind]
velocity = [3.0, 0.0, 1.0]
turbulence = 0.3
[[flag]]
name = "cloth"
origin = [0.0, 1.0, 0.0]
width = 0.6
height = 0.4
resolution = [64, 64]
mass = 10.0
stiffness = 200.0
damping = 0.02
fixed = "pole"
)" + extra;
  auto scene = parse_scene(text, "large_scene", kinds, stages);
  if (!scene) throw std::runtime_error(scene.error().to_string());
  return std::move(scene->model);
}

// A rope, [[contact]] links, obstacles by geometry and by conditional links.
const std::string kStages = R"(
[[rope]]
name = "rope"
start = [0.3, 0.9, 0.02]
end = [0.3, 0.5, 0.02]
points = 8
mass = 0.05
stiffness = 100.0
fixed = "start"
[[contact]]
between = ["cloth", "rope"]
stiffness = 100.0
threshold = 0.03
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
)";

struct Outcome {
  std::uint64_t hash = 0;
  std::set<int> threads_seen;
  std::uint64_t contacts = 0;  // self-collision's, particle pairs and particle-triangle
};

// `threads` 1 or 2: fixed. 0: the default, told that a second core is free for 3 steps, then
// busy for 3, and so on (asked before every step, and followed as told: no timed trial).
Outcome run(const Model& model, const std::string& scheme, ImplicitSolver solver, int threads,
            int steps) {
  SimulationSettings s = test::settings(scheme == "implicit_euler" ? 1e-3 : 1e-4, scheme.c_str());
  s.implicit.solver = solver;
  s.threads = threads;
  Simulator sim(model, s);
  Outcome out;
  if (threads == 0) {
    EXPECT_TRUE(sim.follows_cores());
    sim.set_core_sampling(
        {[asked = 0]() mutable { return (asked++ / 3) % 2 == 0 ? 2 : 1; }, 0.0, 0});
  } else {
    EXPECT_FALSE(sim.follows_cores());
  }
  for (int k = 0; k < steps; ++k) {
    if (!sim.step()) {
      ADD_FAILURE() << sim.blow_up()->message;
      break;
    }
    out.threads_seen.insert(sim.threads());
  }
  out.hash = state_hash(sim.state());
  for (const auto& c : sim.profile().counters())
    if (c.name == "self_contacts" || c.name == "self_triangle_contacts") out.contacts += c.total;
  return out;
}

TEST(FollowCores, ThreadsChangingMidRunKeepTheTrajectory) {
#ifdef _OPENMP
  if (omp_get_num_procs() < 2) GTEST_SKIP() << "one core: the thread count cannot change";
#else
  GTEST_SKIP() << "built without OpenMP";
#endif
  // A radius of two spacings (0.0095 m) beyond a topological radius of one: contacts from the
  // first step on (checked below), without waiting for the cloth to fold; soft enough for the
  // step.
  const std::string self =
      "[self_collision]\ngroups = [\"cloth\"]\nradius = 0.02\ntopological_radius = 1\n"
      "stiffness = 2.0\n";
  const std::string triangles = self + "primitive = \"triangles\"\n";  // checked under vbd
  const std::string facets =
      "[[obstacle]]\nname = \"box\"\nmethod = \"facets\"\nshape = \"cube\"\n"
      "position = [0.35, 0.6, 0.1]\nscale = [0.06, 0.06, 0.06]\ncollides_with = [\"cloth\"]\n";
  struct Case {
    std::string scheme;
    ImplicitSolver solver;
    std::string extra;
  };
  const Case cases[] = {
      {"leapfrog", ImplicitSolver::matrix_free, kStages + self + facets},
      {"implicit_euler", ImplicitSolver::matrix_free, kStages + self + facets},
      {"implicit_euler", ImplicitSolver::vbd, kStages + triangles + facets},
      {"implicit_euler", ImplicitSolver::eigen, kStages + self},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(c.scheme + " (" + std::string(to_string(c.solver)) + ") " +
                 (c.extra.find("triangles") != std::string::npos ? "triangles" : "points"));
    const Model model = large_scene(c.extra);
    const int steps = 9;
    const Outcome one = run(model, c.scheme, c.solver, 1, steps);
    const Outcome two = run(model, c.scheme, c.solver, 2, steps);
    const Outcome following = run(model, c.scheme, c.solver, 0, steps);
    EXPECT_EQ(following.threads_seen, (std::set<int>{1, 2}));
    if (!c.extra.empty()) {
      EXPECT_GT(following.contacts, 0u);
    }
    EXPECT_EQ(one.hash, two.hash);
    EXPECT_EQ(following.hash, one.hash);
  }
}

// A thread count the user chose is never changed, whatever the cores say.
TEST(FollowCores, ChosenThreadsStay) {
  SimulationSettings s = test::settings(1e-4);
  s.threads = 2;
  Simulator sim(large_scene(""), s);
  sim.set_core_sampling({[] { return 1; }, 0.0, 0});
  ASSERT_TRUE(sim.run_steps(3));
  EXPECT_EQ(sim.threads(), 2);
  EXPECT_FALSE(sim.follows_cores());
}

}  // namespace
}  // namespace maille
