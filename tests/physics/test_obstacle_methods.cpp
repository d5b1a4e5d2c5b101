// The three obstacle methods on the same obstacle: the conditional method's sampled surface
// holds a bead inside its threshold shell; a moving obstacle carries what rests on it (every
// method acts on the velocity relative to the surface); the method switches live, and a scheme
// that cannot run a response stage refuses the switch to facets and keeps the old method.
#include <gtest/gtest.h>

#include <cmath>

#include "maille/obstacle.hpp"
#include "maille/scene.hpp"
#include "test_support.hpp"

namespace {

using namespace maille;

Scene bead_over_ball(const std::string& obstacle_keys, double bead_y = 1.35,
                     const char* integrator = "leapfrog") {
  const std::string text = std::string("[simulation]\nintegrator = \"") + integrator +
                           "\"\nstep = 2e-4\n"
                           "[[mass]]\nname = \"bead\"\nmass = 0.01\nposition = [0.0, " +
                           std::to_string(bead_y) +
                           ", 0.0]\n"
                           "[[obstacle]]\nname = \"ball\"\nshape = \"sphere\"\n"
                           "position = [0.0, 1.0, 0.0]\nscale = [0.3, 0.3, 0.3]\n" +
                           obstacle_keys;
  auto scene = parse_scene(text, "ball.toml", LinkKindRegistry::with_builtins(),
                           StageRegistry::with_builtins());
  if (!scene) throw std::runtime_error(scene.error().to_string());
  scene->settings.threads = 1;
  return std::move(*scene);
}

// Sampled at spacing s = threshold and acting within s, the surface holds the bead between the
// true surface and the threshold: its resting depth into the shell is in (0, s), and it rests.
TEST(ObstacleMethods, ConditionalSamplesHoldABeadInsideTheThresholdShell) {
  const Real s = 0.02;
  Scene scene = bead_over_ball(
      "method = \"conditional\"\nthreshold = 0.02\nstiffness = 400.0\n"
      "damping = 0.5\nresolution = 32\n");
  Simulator sim(std::move(scene.model), scene.settings);
  ASSERT_TRUE(sim.run_steps(20000));
  const Vec3 x = sim.state().x()[0];
  const Real above = norm(x - Vec3{0, 1, 0}) - Real(0.3);
  EXPECT_GT(above, 0);
  EXPECT_LT(above, s);
  EXPECT_LT(norm(sim.state().v()[0]), 1e-3);
}

// A plane rising at 0.5 m/s carries a bead resting on it: after a second the bead moves with it
// (damping on the relative velocity), m g / k below its surface for the geometric method, on
// it for facets.
TEST(ObstacleMethods, AMovingObstacleCarriesWhatRestsOnIt) {
  for (const char* method : {"geometric", "facets"}) {
    const std::string keys =
        std::string("method = \"") + method + "\"\n" +
        (std::string(method) == "facets" ? "alpha = 0.0\n" : "stiffness = 400.0\ndamping = 2.0\n");
    const std::string text =
        "[simulation]\nstep = 1e-4\n"
        "[[mass]]\nname = \"bead\"\nmass = 0.01\nposition = [0.0, 0.0000001, 0.0]\n"
        "[[obstacle]]\nname = \"lift\"\nshape = \"plane\"\nscale = [2.0, 1.0, 2.0]\n"
        "motion = { path = \"translate\", velocity = [0.0, 0.5, 0.0] }\n" +
        keys;
    auto scene = parse_scene(text, "lift.toml", LinkKindRegistry::with_builtins(),
                             StageRegistry::with_builtins());
    ASSERT_TRUE(scene) << scene.error().to_string();
    scene->settings.threads = 1;
    Simulator sim(std::move(scene->model), scene->settings);
    ASSERT_TRUE(sim.run_steps(10000));
    const double plane = 0.5 * sim.state().time;
    const double sink = std::string(method) == "geometric" ? 0.01 * 9.81 / 400 : 0;
    EXPECT_NEAR(sim.state().x()[0].y, plane - sink, 1e-4) << method;
    EXPECT_NEAR(sim.state().v()[0].y, 0.5, 1e-3) << method;
  }
}

TEST(ObstacleMethods, TheMethodSwitchesLive) {
  Scene scene = bead_over_ball("stiffness = 400.0\ndamping = 0.3\n");
  Simulator sim(std::move(scene.model), scene.settings);
  ASSERT_TRUE(sim.run_steps(2000));
  // Each method, switched in, catches the bead dropped again from above the ball and holds it
  // on the surface: within the sag m g / k = 2.5e-4 m below it (geometric), on the inscribed
  // mesh (facets: its faces lie up to 1 - cos(pi / 48) = 0.2 % inside) or inside the
  // threshold shell (conditional, 0.02 m).
  for (const char* method : {"facets", "conditional", "geometric", "facets"}) {
    sim.set_stage_option("obstacle:ball", "method", method);
    const auto options = sim.stage_options();
    ASSERT_EQ(options.size(), 1u);
    EXPECT_EQ(options[0].options[0].name, "method");
    EXPECT_EQ(options[0].options[0].value, method);
    sim.state_for_editing().x()[0] = {0, Real(1.35), 0};
    sim.state_for_editing().v()[0] = {};
    ASSERT_TRUE(sim.run_steps(10000)) << method;
    const Real r = norm(sim.state().x()[0] - Vec3{0, 1, 0});
    EXPECT_GT(r, 0.299) << method;
    EXPECT_LT(r, 0.3 + 0.02) << method;
  }
}

TEST(ObstacleMethods, ASchemeThatCannotRespondKeepsTheOldMethod) {
  Scene scene = bead_over_ball("", 1.35, "rk4");
  Simulator sim(std::move(scene.model), scene.settings);
  EXPECT_THROW(sim.set_stage_option("obstacle:ball", "method", "facets"), std::invalid_argument);
  EXPECT_EQ(sim.stage_options()[0].options[0].value, "geometric");
  EXPECT_TRUE(sim.run_steps(100));
}

}  // namespace
