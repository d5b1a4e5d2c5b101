// Every example scene loads, validates and runs without a blow-up; a few carry a physical check
// of what the example is meant to show.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <optional>

#include "maille/scene.hpp"

namespace maille {
namespace {

std::vector<std::filesystem::path> examples() {
  std::vector<std::filesystem::path> out;
  for (const auto& e : std::filesystem::directory_iterator(MAILLE_SOURCE_DIR "/examples"))
    if (e.path().extension() == ".toml") out.push_back(e.path());
  std::sort(out.begin(), out.end());
  return out;
}

// Loads an example into `sim`. A scene that fails to load fails the calling test (wrap the call
// in ASSERT_NO_FATAL_FAILURE) instead of being dereferenced.
void load(const std::string& name, std::optional<Simulator>& sim) {
  auto scene = load_scene(std::string(MAILLE_SOURCE_DIR "/examples/") + name + ".toml");
  ASSERT_TRUE(scene.ok()) << scene.error().to_string();
  sim.emplace(std::move(scene->model), scene->settings);
}

double mean_y(const Simulator& sim, const std::string& group) {
  const Group* g = sim.model().group(group);
  double y = 0;
  for (std::uint32_t i = g->first; i < g->first + g->count; ++i) y += sim.state().x()[i].y;
  return y / g->count;
}

class Example : public ::testing::TestWithParam<std::filesystem::path> {};

// One simulated second of each (or its whole duration if shorter), at the scene's own step,
// which must be inside the stability estimate; every position and velocity is finite at the
// end. Every file in examples/ is a case (the list is read from the directory), so a new
// example is covered by adding it, and the gallery (scripts/gallery.sh) renders the same list.
// On the CPU (the reference; examples written for the GPU backend run there too), and at most
// 1e7 particle-steps (at least 50 steps): the GPU example's 262 144 particles would take 20
// minutes for its second (tests/gpu runs the GPU backend).
TEST_P(Example, RunsStablyForOneSecond) {
  auto scene = load_scene(GetParam());
  ASSERT_TRUE(scene.ok()) << scene.error().to_string();
  scene->settings.backend = "cpu";
  Simulator sim(std::move(scene->model), scene->settings);
  EXPECT_LE(sim.settings().step, sim.stability().max_step) << "scene step beyond stability";
  const double t = std::min(1.0, sim.settings().duration);
  const auto budget = std::max<std::uint64_t>(50, 10'000'000 / sim.model().points.size());
  ASSERT_TRUE(sim.run_steps(std::min(static_cast<std::uint64_t>(t / sim.settings().step), budget)))
      << sim.blow_up()->message;
  for (std::size_t i = 0; i < sim.state().size(); ++i) {
    const Vec3 x = sim.state().x()[i], v = sim.state().v()[i];
    ASSERT_TRUE(std::isfinite(x.x) && std::isfinite(x.y) && std::isfinite(x.z) &&
                std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z))
        << "point " << i << " not finite at t = " << sim.state().time;
  }
}

INSTANTIATE_TEST_SUITE_P(Scenes, Example, ::testing::ValuesIn(examples()),
                         [](const auto& p) { return p.param.stem().string(); });

TEST(Examples, AtLeastSevenScenes) {
  EXPECT_GE(examples().size(), 7u);
}

// The jelly cube falls, is stopped by the floor of conditional links (never sinks through:
// its lowest point stays above the floor minus the threshold) and comes to rest on it.
TEST(Examples, JellyCubeBouncesAndRestsOnTheFloor) {
  std::optional<Simulator> loaded;
  ASSERT_NO_FATAL_FAILURE(load("jelly_cube_bounce", loaded));
  Simulator& sim = *loaded;
  const Group* cube = sim.model().group("cube");
  double lowest = 1e9;
  for (int i = 0; i < 30; ++i) {
    ASSERT_TRUE(sim.run_steps(1000));
    for (std::uint32_t p = cube->first; p < cube->first + cube->count; ++p)
      lowest = std::min<double>(lowest, sim.state().x()[p].y);
  }
  EXPECT_GT(lowest, 0.0);                              // never through the floor plane
  EXPECT_LT(lowest, 0.1);                              // but it did reach the floor's contact layer
  EXPECT_NEAR(mean_y(sim, "cube"), 0.1 + 0.25, 0.08);  // at rest on the contact layer
}

// Two balls collide through conditional links: momentum is conserved (internal forces only),
// and they exchange it: each ends up moving away from the other.
TEST(Examples, LatticeBallsExchangeMomentum) {
  std::optional<Simulator> loaded;
  ASSERT_NO_FATAL_FAILURE(load("lattice_balls_collide", loaded));
  Simulator& sim = *loaded;
  const Vec3 p0 = total_momentum(sim.model(), sim.state().v());
  ASSERT_TRUE(sim.run_steps(15000));
  const Vec3 p1 = total_momentum(sim.model(), sim.state().v());
  EXPECT_LT(norm(p1 - p0), 1e-9);
  auto group_vx = [&](const char* name) {
    const Group* g = sim.model().group(name);
    double v = 0;
    for (std::uint32_t i = g->first; i < g->first + g->count; ++i) v += sim.state().v()[i].x;
    return v / g->count;
  };
  EXPECT_LT(group_vx("left"), -0.3);
  EXPECT_GT(group_vx("right"), 0.3);
}

// The load dropped on the rope bridge is caught: it ends above the banks' level minus the sag.
TEST(Examples, RopeBridgeCatchesTheLoad) {
  std::optional<Simulator> loaded;
  ASSERT_NO_FATAL_FAILURE(load("rope_bridge", loaded));
  Simulator& sim = *loaded;
  ASSERT_TRUE(sim.run_steps(30000));
  EXPECT_GT(mean_y(sim, "load"), -1.0);
  EXPECT_LT(sim.energies().kinetic, 5.0);
}

}  // namespace
}  // namespace maille
