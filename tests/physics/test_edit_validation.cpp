// Validation apart from construction: edit_model refuses a model that is not valid and leaves
// model and state exactly as they were; what the facet stage evolves (whether its one-time
// inside sweep was made) lives in the State, so a fresh simulator that resumes a copy of the
// State continues exactly as the uninterrupted one.
#include <gtest/gtest.h>

#include <functional>
#include <string>

#include "maille/link_registry.hpp"
#include "maille/scene.hpp"
#include "test_support.hpp"

namespace {

using namespace maille;

TEST(EditValidation, CheckModelNamesWhatIsOutOfRange) {
  Model m = test::oscillator(1, 10, 0, 1, 0.1);
  EXPECT_EQ(check_model(m), "");
  Model bad_link = m;
  bad_link.links.pool<Spring>().add({0, 7}, {1, 1});
  EXPECT_NE(check_model(bad_link).find("joins points 0 and 7, but the model has 2 points"),
            std::string::npos)
      << check_model(bad_link);
  Model bad_face = m;
  bad_face.surface.triangles.push_back({0, 1, 2});
  EXPECT_NE(check_model(bad_face).find("face 0 has corner 2"), std::string::npos);
  Model bad_group = m;
  bad_group.groups.push_back({"g", "points", 1, 5});
  EXPECT_NE(check_model(bad_group).find("group 'g' spans points 1..5"), std::string::npos);
  EXPECT_THROW(Simulator(bad_link, test::settings(1e-3)), std::invalid_argument);
}

TEST(EditValidation, ARefusedEditLeavesModelAndStateExactlyAsTheyWere) {
  Simulator sim(test::oscillator(1, 10, 0.1, 1, 0.1), test::settings(1e-3));
  ASSERT_TRUE(sim.run_steps(20));
  const std::uint64_t state_before = state_hash(sim.state());
  const std::size_t links_before = sim.model().links.total();
  // The edit adds a point and a link to a point that does not exist: refused whole (the added
  // point would have resized the state).
  EXPECT_THROW(sim.edit_model([](Model& m) {
    const auto p = m.points.add(PointKind::free, 1, {2, 0, 0});
    m.links.pool<Spring>().add({p, p + 5}, {1, 1});
  }),
               std::invalid_argument);
  EXPECT_EQ(sim.model().points.size(), 2u);
  EXPECT_EQ(sim.model().links.total(), links_before);
  EXPECT_EQ(state_hash(sim.state()), state_before);
  // And the simulator runs on as if nothing had been asked.
  Simulator twin(test::oscillator(1, 10, 0.1, 1, 0.1), test::settings(1e-3));
  ASSERT_TRUE(twin.run_steps(20));
  ASSERT_TRUE(sim.run_steps(20));
  ASSERT_TRUE(twin.run_steps(20));
  EXPECT_EQ(state_hash(sim.state()), state_hash(twin.state()));
}

// edit_parameters validates too: a mass out of bounds, a mass without its inverse, a stiffness
// beyond the bound, or a structural change sneaked in with a bad link are refused with the reason, and
// the simulator runs on exactly as its twin that was never asked. (A NaN is refused by the same
// comparison; these tests trap floating-point exceptions, so it is not made here.)
TEST(EditValidation, ARefusedParameterEditLeavesModelAndStateExactlyAsTheyWere) {
  Simulator sim(test::oscillator(1, 10, 0.1, 1, 0.1), test::settings(1e-3));
  ASSERT_TRUE(sim.run_steps(20));
  const std::uint64_t state_before = state_hash(sim.state());
  const Real stiffness_before = sim.model().links.pools()[0]->param(0, 0);
  auto refused = [&](const std::function<void(Model&)>& edit) {
    try {
      sim.edit_parameters(edit);
    } catch (const std::invalid_argument& e) {
      return std::string(e.what());
    }
    return std::string("accepted");
  };
  EXPECT_NE(refused([](Model& m) {
              m.points.mass[1] = -1;
              m.points.inv_mass[1] = -1;
            }).find("point 1 has mass -1 kg, outside [1e-12, 1e12] kg"),
            std::string::npos);
  EXPECT_NE(refused([](Model& m) { m.points.mass[1] = 2; }).find("has inv_mass 1 for mass 2 kg"),
            std::string::npos);
  const std::string huge = refused([](Model& m) { m.links.pools()[0]->scale_param(0, 1e13); });
  EXPECT_NE(huge.find("link (0) has stiffness = 1e+14, outside [0, 1e+12] N/m"), std::string::npos)
      << huge;
  EXPECT_NE(refused([](Model& m) { m.links.pool<Spring>().add({0, 9}, {1, 1}); })
                .find("joins points 0 and 9"),
            std::string::npos);
  EXPECT_EQ(sim.model().points.mass[1], 1);
  EXPECT_EQ(sim.model().links.total(), 1u);
  EXPECT_EQ(sim.model().links.pools()[0]->param(0, 0), stiffness_before);
  EXPECT_EQ(state_hash(sim.state()), state_before);
  Simulator twin(test::oscillator(1, 10, 0.1, 1, 0.1), test::settings(1e-3));
  ASSERT_TRUE(twin.run_steps(40));
  ASSERT_TRUE(sim.run_steps(20));
  EXPECT_EQ(state_hash(sim.state()), state_hash(twin.state()));
  // A valid edit is taken: mass and inverse together.
  EXPECT_EQ(refused([](Model& m) {
              m.points.mass[1] = 2;
              m.points.inv_mass[1] = Real(0.5);
            }),
            "accepted");
  EXPECT_EQ(sim.model().points.mass[1], 2);
}

const char* kOverCube = R"(
[simulation]
step = 1e-3
[[mass]]
name = "a"
position = [0, 0.5, 0]
[[mass]]
name = "b"
position = [0.05, 0.5, 0.05]
[[obstacle]]
name = "cube"
method = "facets"
shape = "cube"
scale = [0.2, 0.2, 0.2]
)";

TEST(EditValidation, TheFacetStagesInsideSweepIsRecordedInTheState) {
  static const LinkKindRegistry kinds = LinkKindRegistry::with_builtins();
  auto scene = parse_scene(kOverCube, "cube.toml", kinds);
  ASSERT_TRUE(scene) << scene.error().to_string();
  Simulator a(scene->model, scene->settings);
  ASSERT_TRUE(a.run_steps(5));
  State s = a.state();
  ASSERT_EQ(s.memory("obstacle:cube"), std::vector<double>{2});  // both particles swept once
  // A particle deep inside the cube (its centre, 0.2 m from every face) after the sweep: the
  // per-step test does not reach it. A fresh simulator given this state must not sweep again,
  // or it would diverge from the one that goes on.
  s.x()[0] = {0, 0, 0};
  s.v()[0] = {0, 0, 0};
  Simulator b(scene->model, scene->settings);
  a.restore(s);
  b.restore(s);
  ASSERT_TRUE(a.run_steps(5));
  ASSERT_TRUE(b.run_steps(5));
  // Still deep inside: no sweep ran (a sweep puts it on the surface, 0.2 m out), in either.
  EXPECT_LT(norm(a.state().x()[0]), Real(0.1));
  EXPECT_EQ(state_hash(a.state()), state_hash(b.state()));
  // A reset starts a fresh State: the sweep is made again (the particle starts outside here).
  a.reset();
  ASSERT_TRUE(a.run_steps(1));
  EXPECT_EQ(a.state().stage_memory.size(), 1u);
}

}  // namespace
