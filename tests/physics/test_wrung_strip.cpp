// The wrung strip (examples/wrung_cloth.toml at 24 x 12): the twist makes the strip press on
// itself and its edges cross edges. With edge-edge contacts beside the particle-face ones, no
// pair of its triangles crosses at any step of the first 2.4 turns (4.8 s; check =
// "every_step" stops a run at the first crossing), by vertex block descent at 1/60 s and by
// leapfrog; with particle-face contacts alone it crosses within 1.2 turns. This coarse
// strip (4.3 cm spacing, a 6 mm layer) creases so tightly that its in-plane compression
// overcomes the penalty (k s = 4.8 N): the conservative bounds then hold each pair at the
// stencils' floor (law::stencil_bound; without it the distance fell to 1e-11 m and rounding
// crossed the diagonals of two neighbouring cells, VBD at 3.4 s, leapfrog at 2.76 s). It crosses
// at last next to the driven end (VBD at 5.68 s, leapfrog at 5.80 s), where the drive moves a
// face's driven corners onto the free points the bounds hold: outside the guarantee
// (docs/implicit.md, "Intersection-free cloth: what holds"). The example's 48 x 24 strip holds
// all three turns (0 crossings in 6 s by VBD). An independent brute-force count (every pair of
// faces sharing no corner, each edge of one against the other by Moller and Trumbore's
// segment-triangle test) over sampled states finds none either, where the same count finds the
// crossings of two cloths placed through each other.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <span>
#include <stdexcept>
#include <string>
#include <vector>

#include "../intersections.hpp"
#include "maille/scene.hpp"
#include "maille/simulator.hpp"

namespace {

using namespace maille;

// The independent count (tests/intersections.hpp: every pair of faces sharing no corner, each
// edge of one against the other by Moller and Trumbore's segment-triangle test).
std::size_t brute_force_crossings(std::span<const Vec3> x,
                                  const std::vector<std::array<std::uint32_t, 3>>& faces) {
  return test::count_self_intersections(x, faces);
}

Scene strip(std::vector<std::string> sets) {
  sets.push_back("flag[0].resolution=[24,12]");
  sets.push_back("self_collision.check=every_step");
  auto s = load_scene(std::string(MAILLE_SOURCE_DIR "/examples/wrung_cloth.toml"), sets);
  if (!s) throw std::runtime_error(s.error().to_string());
  return std::move(s.value());
}

// Runs to the scene's end; every `sample` steps the brute-force count must be zero too.
void wring(const Scene& scene, std::uint64_t sample) {
  Simulator sim(scene.model, scene.settings);
  const auto steps = std::uint64_t(std::llround(scene.settings.duration / scene.settings.step));
  for (std::uint64_t k = 0; k < steps; ++k) {
    ASSERT_TRUE(sim.step()) << "step " << k << ": "
                            << (sim.blow_up() ? sim.blow_up()->message : std::string("stopped"));
    if (k % sample == 0 || k + 1 == steps) {
      ASSERT_EQ(brute_force_crossings(sim.state().x(), scene.model.surface.triangles), 0u)
          << "step " << k;
    }
  }
}

TEST(WrungStrip, BruteForceCountFindsCrossedCloths) {
  // The check's own scene: two cloths placed through each other (tests/data/crossed_cloths.toml).
  auto s = load_scene(std::string(MAILLE_TEST_DATA "/crossed_cloths.toml"));
  ASSERT_TRUE(s) << s.error().to_string();
  EXPECT_GT(brute_force_crossings(s->model.points.initial_position, s->model.surface.triangles),
            5u);
}

TEST(WrungStrip, TwoTurnsByVertexBlockDescentNeverCross) {
  wring(strip({"simulation.duration=4.8"}), 30);
}

// Leapfrog at 2e-4 s, likewise.
TEST(WrungStrip, TwoTurnsByLeapfrogNeverCross) {
  wring(
      strip({"simulation.integrator=leapfrog", "simulation.step=2e-4", "simulation.duration=4.8"}),
      2000);
}

}  // namespace
