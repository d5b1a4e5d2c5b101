// [[attractor]] (src/stages/attractor.cpp) against Kepler: a circular orbit's period
// 2 pi sqrt(r^3 / mu), an eccentric orbit's energy, and the softened potential's speed at the
// centre, sqrt(2 mu (1/eps - 1/sqrt(R^2 + eps^2))) for a point released at rest at R.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <sstream>
#include <string>

#include "maille/link_registry.hpp"
#include "maille/scene.hpp"
#include "maille/simulator.hpp"
#include "maille/stage_registry.hpp"
#include "maille/state.hpp"
#include "test_support.hpp"

namespace {

using namespace maille;

Scene from_text(const std::string& text) {
  return test::scene_from_text(text, "attractor.toml");
}

// One 2 kg planet at (r, 0, 0) with velocity (0, 0, v), a sun of strength mu at the origin, no
// gravity.
std::string orbit(double r, double v, double mu, double step, double softening = 0) {
  std::ostringstream t;
  t.precision(17);
  t << "[scene]\nname = \"orbit\"\n[simulation]\nstep = " << step
    << "\nduration = 1000.0\nintegrator = \"velocity_verlet\"\n[fields]\ngravity = [0.0, 0.0, "
       "0.0]\n"
    << "[[mass]]\nname = \"planet\"\nposition = [" << r << ", 0.0, 0.0]\nvelocity = [0.0, 0.0, "
    << v << "]\nmass = 2.0\n"
    << "[[attractor]]\nname = \"sun\"\nposition = [0.0, 0.0, 0.0]\nstrength = " << mu
    << "\nsoftening = " << softening << "\n";
  return t.str();
}

// velocity_verlet is second order: at 2000 steps an orbit the period's error is of order
// (omega h)^2 = 1e-5; 1e-4 relative leaves it a factor 10, and a wrong law (a force off by a
// factor of r, or of 2) misses by far more.
TEST(Attractor, ACircularOrbitHasKeplersPeriod) {
  const double r = 1.5, mu = 4.0, period = 2 * std::numbers::pi * std::sqrt(r * r * r / mu);
  const double h = period / 2000;
  Scene scene = from_text(orbit(r, std::sqrt(mu / r), mu, h));
  Simulator sim(scene.model, scene.settings);
  double crossing = -1, z_before = 0, largest_gap = 0;
  for (int step = 1; step <= 2100 && crossing < 0; ++step) {
    z_before = sim.state().x()[0].z;
    ASSERT_TRUE(sim.run_steps(1));
    const Vec3 x = sim.state().x()[0];
    largest_gap = std::max(largest_gap, std::abs(std::sqrt(x.x * x.x + x.z * x.z) - r));
    if (step > 1000 && z_before < 0 && x.z >= 0)  // back across the start's half-plane
      crossing = (step - 1 + z_before / (z_before - x.z)) * h;
  }
  ASSERT_GT(crossing, 0) << "no full orbit";
  EXPECT_NEAR(crossing / period, 1.0, 1e-4);
  EXPECT_LT(largest_gap / r, 1e-4);      // stays circular
  EXPECT_EQ(sim.state().x()[0].y, 0.0);  // in its plane
}

// An orbit of eccentricity 0.36 (0.8 of the circular speed) keeps kinetic + attractor energy:
// velocity Verlet is symplectic, its energy error bounded, O((omega h)^2) at perihelion.
TEST(Attractor, AnEccentricOrbitKeepsItsEnergy) {
  const double r = 1.0, mu = 1.0, v = 0.8 * std::sqrt(mu / r);
  Scene scene = from_text(orbit(r, v, mu, 2 * std::numbers::pi / 4000));
  Simulator sim(scene.model, scene.settings);
  const double e0 = 0.5 * 2.0 * v * v - 2.0 * mu / r;  // J: negative, bound
  EXPECT_NEAR(sim.energies().total(), e0, 1e-12);
  double worst = 0;
  for (int k = 0; k < 30; ++k) {  // three orbits (the period is 0.72 of the circular one)
    ASSERT_TRUE(sim.run_steps(400));
    worst = std::max(worst, std::abs(sim.energies().total() - e0));
  }
  EXPECT_LT(worst / std::abs(e0), 1e-4);
}

// Softened, the pull is finite at the sun: a planet released at rest at R falls through it,
// where its speed is sqrt(2 mu (1/eps - 1/sqrt(R^2 + eps^2))) (energy), and out to R again.
TEST(Attractor, ASoftenedAttractorLetsAPointFallThroughAtTheSpeedItsPotentialGives) {
  const double R = 1.0, mu = 1.0, eps = 0.1;
  Scene scene = from_text(orbit(R, 0.0, mu, 1e-4, eps));
  Simulator sim(scene.model, scene.settings);
  double fastest = 0, farthest_beyond = 0;
  for (int step = 0; step < 40000; ++step) {
    ASSERT_TRUE(sim.run_steps(1));
    fastest = std::max(fastest, std::abs(sim.state().v()[0].x));
    farthest_beyond = std::max(farthest_beyond, -sim.state().x()[0].x);
  }
  const double expected = std::sqrt(2 * mu * (1 / eps - 1 / std::sqrt(R * R + eps * eps)));
  // The largest sampled speed is within one step's change of the peak: |a| h / v at most
  // (mu / eps^2) 1e-4 / 4.2 = 2.4e-3 relative, where the acceleration is 0 at the peak itself.
  EXPECT_NEAR(fastest / expected, 1.0, 1e-3);
  EXPECT_NEAR(farthest_beyond, R, 1e-3);  // out to -R on the far side (energy)
}

// A negative strength repels: a point at rest accelerates away at mu / r^2.
TEST(Attractor, ANegativeStrengthPushesAway) {
  Scene scene = from_text(orbit(2.0, 0.0, -8.0, 1e-5));
  Simulator sim(scene.model, scene.settings);
  ASSERT_TRUE(sim.run_steps(10));
  const double a = sim.state().v()[0].x / 1e-4;  // 10 steps of 1e-5 s
  EXPECT_NEAR(a, 8.0 / 4.0, 1e-3);
}

TEST(Attractor, BadTablesAreRefusedAtTheirKey) {
  const std::string head =
      "[scene]\nname = \"x\"\n[[mass]]\nname = \"p\"\nposition = [1.0, 0.0, 0.0]\nmass = 1.0\n";
  auto fails = [&](const std::string& table, const std::string& needle) {
    auto s = parse_scene(head + table, "bad.toml", LinkKindRegistry::with_builtins(),
                         StageRegistry::with_builtins());
    ASSERT_FALSE(s) << table;
    EXPECT_NE(s.error().to_string().find(needle), std::string::npos) << s.error().to_string();
  };
  fails("[[attractor]]\nposition = [0.0, 0.0, 0.0]\n", "strength");
  fails("[[attractor]]\nstrength = 1.0\n", "position");
  fails("[[attractor]]\nposition = [0.0, 0.0, 0.0]\nstrength = 1.0\ngroups = [\"nope\"]\n",
        "bad.toml:10");
  fails("[[attractor]]\nposition = [0.0, 0.0, 0.0]\nstrength = 1.0\nsoftening = -1.0\n",
        "softening");
  fails(
      "[[attractor]]\nposition = [0.0, 0.0, 0.0]\nstrength = 1.0\n"
      "[[attractor]]\nposition = [1.0, 0.0, 0.0]\nstrength = 1.0\n",
      "another attractor is named 'attractor'");
}

// Unsoftened, its stiffness has no bound: the run says the stability estimate cannot see it;
// softened (eps = 0.1 m), the estimate holds m |mu| / eps^3 = 2 x 1 / 1e-3 = 2000 N/m, so
// omega^2 = 1000 at the planet, and nothing is said.
TEST(Attractor, AnUnsoftenedAttractorSaysTheStabilityEstimateCannotSeeIt) {
  Scene bare = from_text(orbit(1.0, 1.0, 1.0, 1e-3));
  Simulator bare_sim(bare.model, bare.settings);
  const auto said = bare_sim.stage_warnings();
  ASSERT_EQ(said.size(), 1u);
  EXPECT_NE(said[0].find("attractor:sun"), std::string::npos) << said[0];
  EXPECT_NE(said[0].find("softening"), std::string::npos) << said[0];
  Scene soft = from_text(orbit(1.0, 1.0, 1.0, 1e-3, 0.1));
  Simulator soft_sim(soft.model, soft.settings);
  EXPECT_TRUE(soft_sim.stage_warnings().empty());
  EXPECT_NEAR(soft_sim.stability().omega, std::sqrt(1000.0), 1e-9);  // k / m = 2000 / 2
  EXPECT_EQ(bare_sim.stability().omega, 0.0);                        // left out, and said so
}

TEST(Attractor, ItsStageIsNamedAfterIt) {
  Scene scene = from_text(orbit(1.0, 1.0, 1.0, 1e-3));
  ASSERT_EQ(scene.model.stages.size(), 1u);
  EXPECT_EQ(scene.model.stages[0].name, "attractor:sun");
}

}  // namespace
