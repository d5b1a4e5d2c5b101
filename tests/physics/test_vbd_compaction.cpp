// VBD's sweeps load only the contact candidates near enough to act (VertexBlockDescent::
// compact): the stages find their candidates within their radius plus a margin for the whole
// step's motion, most of them far from acting; the sweeps take those within the radius plus
// their points' allowances. That it changes no bit is the implicit golden hashes' claim
// (tests/golden/implicit/: recorded before the compaction, unchanged by it); here, that it
// leaves most candidates out of the sweeps on a settled drape, and that the counters say so.
#include <gtest/gtest.h>

#include <string>

#include "maille/scene.hpp"
#include "maille/simulator.hpp"

namespace {

using namespace maille;

std::uint64_t counter(const Simulator& sim, const char* name) {
  for (const auto& c : sim.profile().counters())
    if (c.name == name) return c.last;
  ADD_FAILURE() << "no counter " << name;
  return 0;
}

// cloth_on_sphere (point-triangle layer and the stage's point pairs) at 1/60 s, 48^2, once the
// cloth lies on the ball: the stage's margin still covers its fall, the points barely move.
TEST(VbdCompaction, a_settled_drape_sweeps_a_small_share_of_its_candidates) {
  const std::vector<std::string> sets = {
      "simulation.integrator=implicit_euler", "simulation.implicit.solver=vbd",
      "simulation.step=0.016666666666666666", "flag[0].resolution=[48,48]"};
  auto scene = load_scene(std::string(MAILLE_SOURCE_DIR "/examples/cloth_on_sphere.toml"), sets);
  ASSERT_TRUE(scene.ok()) << scene.error().to_string();
  scene->settings.threads = 1;
  Simulator sim(std::move(scene->model), scene->settings);
  ASSERT_TRUE(sim.run_steps(120));  // 2 s: fallen and settled
  const std::uint64_t all = counter(sim, "vbd_contact_candidates");
  const std::uint64_t swept = counter(sim, "vbd_contact_candidates_swept");
  EXPECT_GT(all, 1000u);
  EXPECT_GT(swept, 0u);  // the contacts that hold the cloth are swept
  EXPECT_LT(swept * 2, all) << swept << " of " << all << " candidates swept";
}

}  // namespace
