// The gallery's implicit examples (every examples/*.toml whose integrator is implicit_euler)
// hold the quality docs/implicit.md promises at their own large step, over their whole
// duration, on one thread: the largest stretch of any spring-damper within 10 % (sampled every
// step), no point deeper than 2 mm in a geometric obstacle (the stage's depth gauge, every
// step), and, with self-collision, no pair of the cloth's triangles crossing (every step). A
// new implicit example joins by being added to examples/ (kNotDrapes lists those that are not
// drapes, and why).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "../intersections.hpp"
#include "cloth_measures.hpp"
#include "maille/scene.hpp"
#include "maille/simulator.hpp"

namespace maille {
namespace {

// Implicit examples that are not drapes, with why they are measured elsewhere.
constexpr std::pair<std::string_view, std::string_view> kNotDrapes[] = {
    {"wrung_cloth",
     "a wringing: its ends are held 1 m apart while it winds three turns, so it stretches by "
     "construction; its crossings are tested by physics.WrungStrip and its trajectory by the "
     "golden hash"},
};

std::vector<std::filesystem::path> implicit_examples() {
  std::vector<std::filesystem::path> out;
  for (const auto& e : std::filesystem::directory_iterator(MAILLE_SOURCE_DIR "/examples")) {
    if (e.path().extension() != ".toml") continue;
    if (std::any_of(std::begin(kNotDrapes), std::end(kNotDrapes),
                    [&](const auto& n) { return e.path().stem() == n.first; }))
      continue;
    auto scene = load_scene(e.path());
    if (scene.ok() && scene->settings.integrator == "implicit_euler") out.push_back(e.path());
  }
  std::sort(out.begin(), out.end());
  return out;
}

using test::largest_stretch;  // cloth_measures.hpp

class ImplicitExample : public ::testing::TestWithParam<std::filesystem::path> {};

TEST_P(ImplicitExample, KeepsStretchDepthAndFoldsApartOverItsDuration) {
  auto loaded = load_scene(GetParam());
  ASSERT_TRUE(loaded.ok()) << loaded.error().to_string();
  Scene scene = std::move(loaded.value());
  scene.settings.backend = "cpu";
  scene.settings.threads = 1;
  scene.settings.publish_every = kNeverEvery;
  const bool self_colliding =
      std::any_of(scene.model.stages.begin(), scene.model.stages.end(),
                  [](const StageSpec& st) { return st.name == "self_collision"; });
  const auto triangles = scene.model.surface.triangles;
  Simulator sim(std::move(scene.model), scene.settings);
  const auto steps =
      static_cast<std::uint64_t>(std::llround(sim.settings().duration / sim.settings().step));
  double stretch = 0, depth = 0;
  std::size_t crossing = 0;
  std::string deepest;
  for (std::uint64_t k = 1; k <= steps; ++k) {
    ASSERT_TRUE(sim.step()) << sim.blow_up()->message;
    stretch = std::max(stretch, largest_stretch(sim));
    for (const auto& gauge : sim.profile().gauges())
      if (gauge.name.starts_with("obstacle_") && gauge.name.ends_with("_depth") &&
          gauge.last > depth) {
        depth = gauge.last;
        deepest = gauge.name + " at step " + std::to_string(k);
      }
    if (self_colliding)
      crossing = std::max(crossing, test::count_self_intersections(sim.state().x(), triangles));
  }
  EXPECT_LE(stretch, 0.10);
  EXPECT_LE(depth, 2e-3) << deepest;
  EXPECT_EQ(crossing, 0u);
  RecordProperty("stretch", std::to_string(stretch));
  RecordProperty("depth_m", std::to_string(depth));
}

INSTANTIATE_TEST_SUITE_P(Scenes, ImplicitExample, ::testing::ValuesIn(implicit_examples()),
                         [](const auto& p) { return p.param.stem().string(); });

TEST(ImplicitExamples, TheGalleryHasTheClothOnTheSphereAndTheHeap) {
  std::vector<std::string> names;
  for (const auto& p : implicit_examples()) names.push_back(p.stem().string());
  EXPECT_NE(std::find(names.begin(), names.end(), "cloth_on_sphere_vbd"), names.end());
  EXPECT_NE(std::find(names.begin(), names.end(), "cloth_heap_vbd"), names.end());
}

}  // namespace
}  // namespace maille
