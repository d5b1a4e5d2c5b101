// `[self_collision] check` and stats.csv's `intersecting_pairs` (maille/intersections.hpp):
// two cloths placed through each other are counted (their crossing is a line across both, so
// the count is about the number of face pairs along it), `every_step` stops the run at step 0
// naming the stage, `off` counts nothing; a drop that never crosses (two_cloths) counts 0.
#include <gtest/gtest.h>

#include <cmath>
#include <sstream>
#include <string>
#include <vector>

#include "maille/link_registry.hpp"
#include "maille/scene.hpp"
#include "maille/simulator.hpp"
#include "maille/stage_registry.hpp"

namespace {

using namespace maille;

// A horizontal 10 x 10 cloth and a vertical one through its middle (the vertical one spans
// y in [-0.25, 0.25], the horizontal lies at y = 0): they cross along a segment.
Scene crossed(const std::string& check) {
  std::ostringstream t;
  t << "[scene]\nname = \"crossed\"\n[simulation]\nstep = 1e-4\nduration = 0.01\n"
    << "output_every = 10\n[fields]\ngravity = [0.0, 0.0, 0.0]\n";
  for (const char* f : {"[[flag]]\nname = \"flat\"\norigin = [-0.25, 0.0, -0.25]\n"
                        "along = [1.0, 0.0, 0.0]\nup = [0.0, 0.0, 1.0]\n",
                        "[[flag]]\nname = \"upright\"\norigin = [-0.2, -0.25, 0.013]\n"
                        "along = [1.0, 0.0, 0.0]\nup = [0.0, 1.0, 0.0]\n"})
    t << f << "width = 0.5\nheight = 0.5\nresolution = [10, 10]\nmass = 0.1\n"
      << "stiffness = 200.0\ndamping = 0.02\nfixed = \"none\"\n";
  t << "[self_collision]\nprimitive = \"triangles\"\ncheck = \"" << check << "\"\n";
  static const LinkKindRegistry kinds = LinkKindRegistry::with_builtins();
  static const StageRegistry stages = StageRegistry::with_builtins();
  auto s = parse_scene(t.str(), "crossed.toml", kinds, stages);
  if (!s) throw std::runtime_error(s.error().to_string());
  return std::move(s.value());
}

std::uint64_t crossing_count(const Simulator& sim) {
  for (const auto& c : sim.profile().counters())
    if (c.name == "intersecting_pairs") return c.last;
  return ~std::uint64_t(0);  // no such column
}

TEST(IntersectionCheck, CrossedClothsAreCountedAtTheStatsCadence) {
  Scene scene = crossed("stats");
  Simulator sim(scene.model, scene.settings);
  std::uint64_t sampled = 0;
  sim.on_sample([&](const EnergySample&, const Profile& p) {
    for (const auto& c : p.counters())
      if (c.name == "intersecting_pairs") sampled = c.last;
  });
  ASSERT_TRUE(sim.step());  // step 0 is sampled
  // The upright cloth's 9 columns of face pairs meet the flat one's faces along the line
  // y = 0, z = 0.013: each of its faces there crosses one or two flat faces.
  EXPECT_GE(sampled, 9u);
  EXPECT_LE(sampled, 4u * 9u);
  EXPECT_EQ(crossing_count(sim), sampled);
}

TEST(IntersectionCheck, EveryStepStopsAtTheFirstCrossingNamingTheStage) {
  Scene scene = crossed("every_step");
  Simulator sim(scene.model, scene.settings);
  EXPECT_FALSE(sim.step());
  ASSERT_TRUE(sim.blow_up());
  EXPECT_EQ(sim.blow_up()->module, "self_collision");
  EXPECT_EQ(sim.blow_up()->step, 0u);
  EXPECT_NE(sim.blow_up()->message.find("cross"), std::string::npos) << sim.blow_up()->message;
}

TEST(IntersectionCheck, OffCountsNothing) {
  Scene scene = crossed("off");
  Simulator sim(scene.model, scene.settings);
  ASSERT_TRUE(sim.step());
  EXPECT_EQ(crossing_count(sim), ~std::uint64_t(0));
}

// A start in intersection is not made worse: the two crossed cloths (with triangles and edge
// pairs) keep at most their starting count of crossing pairs through 0.1 s of leapfrog and
// 6 steps of VBD at 1/60 s (the penalty acts on unsigned distances, so it holds the crossing
// line where it is rather than undoing it: docs/implicit.md, "Intersection-free cloth").
TEST(IntersectionCheck, AStartInIntersectionIsNotMadeWorse) {
  for (const bool implicit : {false, true}) {
    Scene scene = crossed("stats");
    scene.settings.duration = 0.1;
    scene.settings.sample_every = 1;  // the count at every step
    if (implicit) {
      scene.settings.integrator = "implicit_euler";
      scene.settings.step = 1.0 / 60;
      scene.settings.implicit.solver = ImplicitSolver::vbd;
    }
    Simulator sim(scene.model, scene.settings);
    std::uint64_t first = 0, last = 0;
    bool started = false;
    sim.on_sample([&](const EnergySample&, const Profile& p) {
      for (const auto& c : p.counters())
        if (c.name == "intersecting_pairs") {
          if (!started) first = c.last;
          started = true;
          last = c.last;
          EXPECT_LE(c.last, first) << (implicit ? "vbd" : "leapfrog");
        }
    });
    const auto steps = std::uint64_t(std::llround(scene.settings.duration / scene.settings.step));
    ASSERT_TRUE(sim.run_steps(steps));
    EXPECT_GT(first, 0u);
    EXPECT_LE(last, first);
  }
}

TEST(IntersectionCheck, ADropThatNeverCrossesCountsZero) {
  const std::vector<std::string> sets{"self_collision.check=every_step"};
  auto s = load_scene(std::string(MAILLE_SOURCE_DIR "/examples/two_cloths.toml"), sets);
  ASSERT_TRUE(s) << s.error().to_string();
  Simulator sim(s->model, s->settings);
  EXPECT_TRUE(sim.run_steps(3000));  // 0.45 s: the upper cloth lands on the lower one
  EXPECT_FALSE(sim.blow_up());
  EXPECT_EQ(crossing_count(sim), 0u);
}

}  // namespace
