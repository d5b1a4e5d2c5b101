// Modularity: a link kind defined only here, registered here (nothing under src/ knows it),
// runs in a model beside the built-in kinds, from code and from a scene file.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "maille/link_registry.hpp"
#include "maille/links/spring.hpp"
#include "maille/scene.hpp"
#include "maille/simulator.hpp"

namespace {

using maille::Real;
using maille::Vec3;

// A hardening spring: f_a = k3 (|d| - L0)^3 d/|d|, energy k3 (|d| - L0)^4 / 4.
struct CubicSpring {
  static constexpr std::string_view keyword = "cubic_spring";
  struct Params {
    Real k3 = 0;           // N/m^3
    Real rest_length = 0;  // m
  };
  static constexpr std::array<maille::ParamField<Params>, 2> fields{{
      {"k3", "N/m^3", &Params::k3, maille::Bound::positive},
      {"rest_length", "m", &Params::rest_length, maille::Bound::non_negative, {}, true},
  }};
  static Vec3 force(const Vec3& xa, const Vec3& xb, const Vec3&, const Vec3&, const Params& p) {
    const maille::Separation s = maille::separation(xa, xb);
    const Real e = s.length - p.rest_length;
    return s.n * (p.k3 * e * e * e);
  }
  static Real energy(const Vec3& xa, const Vec3& xb, const Params& p) {
    const Real e = maille::norm(xb - xa) - p.rest_length;
    return p.k3 * e * e * e * e / 4;
  }
  // Linearised stiffness at 10 cm of stretch, for the stability estimate.
  static Real stiffness(const Params& p) { return 3 * p.k3 * Real(0.01); }
  static Real damping(const Params&) { return 0; }
};

// From code: a cubic spring (from the left anchor) and a linear spring (to the right anchor) hold
// one mass. Energy is conserved to leapfrog accuracy, which it could not be if the cubic kind's
// forces were missing or wrong (its energy is in the budget). And the bob oscillates about the
// point where the two forces balance, x* with k3 x*^3 = k (-0.5 - x*) (cubic spring at rest at
// x = 0, linear spring at rest at x = -0.5): it passes there at its highest speed.
TEST(CustomKind, RunsBesideBuiltinsFromCode) {
  constexpr double k3 = 5000, k = 20, linear_rest = 1.5;
  maille::Model m;
  m.fields.gravity = {0, 0, 0};
  const auto left = m.points.add(maille::PointKind::fixed, 1, {-1, 0, 0});
  const auto right = m.points.add(maille::PointKind::fixed, 1, {1, 0, 0});
  const auto bob = m.points.add(maille::PointKind::free, 0.1, {0.3, 0, 0});
  m.links.pool<CubicSpring>().add({left, bob}, {k3, 1});
  m.links.pool<maille::Spring>().add({bob, right}, {k, linear_rest});
  maille::SimulationSettings s;
  s.step = 1e-4;
  s.sample_every = 100;
  maille::Simulator sim(std::move(m), s);
  std::vector<double> e;
  sim.on_sample([&](const maille::EnergySample& x, const maille::Profile&) {
    e.push_back(x.energies.total());
  });
  double fastest = 0, where = 0;  // position of the highest speed seen
  for (int i = 0; i < 50000; ++i) {
    ASSERT_TRUE(sim.run_steps(1));
    const double speed = std::abs(sim.state().v()[bob].x);
    if (speed > fastest) fastest = speed, where = sim.state().x()[bob].x;
  }
  const double e0 = e.front();
  EXPECT_GT(e0, 0.5);  // the cubic spring holds most of it: k3 0.3^4 / 4 = 10 J
  for (double v : e) EXPECT_NEAR(v / e0, 1.0, 1e-4);
  EXPECT_EQ(sim.model().links.pools().size(), 2u);

  // The equilibrium: k3 x^3 + k x + k (linear_rest - 1) = 0, monotone in x, by bisection.
  double lo = -1, hi = 1;
  for (int i = 0; i < 200; ++i) {
    const double mid = 0.5 * (lo + hi);
    (k3 * mid * mid * mid + k * mid + k * (linear_rest - 1) > 0 ? hi : lo) = mid;
  }
  const double centre = 0.5 * (lo + hi);
  ASSERT_NEAR(centre, -0.1154, 1e-3);  // neither kind's own rest position (0 or -0.5)
  // Sampled once a step, at ~17 m/s the bob moves 1.7 mm per step (and leapfrog's velocity is
  // half a step off the position): within two steps of travel.
  EXPECT_NEAR(where, centre, 4e-3);
  EXPECT_GT(fastest, 1.0);
}

TEST(CustomKind, UsableFromASceneThroughTheRegistry) {
  maille::LinkKindRegistry kinds = maille::LinkKindRegistry::with_builtins();
  kinds.add<CubicSpring>();
  const char* text = R"(
[fields]
gravity = [0.0, 0.0, 0.0]
[[fixed]]
name = "anchor"
position = [0, 0, 0]
[[mass]]
name = "bob"
position = [1.2, 0, 0]
mass = 0.1
[[link]]
kind = "cubic_spring"
a = "anchor"
b = "bob"
k3 = 5000.0
rest_length = 1.0
[[link]]
kind = "spring_damper"
a = "anchor"
b = "bob"
stiffness = 10.0
)";
  auto scene = maille::parse_scene(text, "inline.toml", kinds);
  ASSERT_TRUE(scene.ok()) << scene.error().to_string();
  EXPECT_NE(scene->model.links.find("cubic_spring"), nullptr);
  EXPECT_NE(scene->model.links.find("spring_damper"), nullptr);
  // The built-in registry does not know the kind: the same text fails there, naming it.
  auto plain = maille::parse_scene(text, "inline.toml", maille::LinkKindRegistry::with_builtins());
  ASSERT_FALSE(plain.ok());
  EXPECT_NE(plain.error().message.find("cubic_spring"), std::string::npos);
  // The cubic spring's force acts: released at 0.2 m of stretch, the bob accelerates inward at
  // k3 0.2^3 / m = 400 m/s^2.
  // (The spring-damper's rest length defaults to the built distance: it is slack here.)
  const std::uint32_t bob = scene->model.group("bob")->first;
  maille::Simulator sim(std::move(scene->model), scene->settings);
  sim.energies();
  EXPECT_NEAR(sim.state().f()[bob].x / 0.1, -(5000 * 0.008) / 0.1, 1e-9);
}

}  // namespace

namespace {

// A spring whose energy is not a number while its force is finite (a kind with a bad energy
// law): the run must stop as a blow-up that says so in words, never "-nan J".
struct NanEnergySpring {
  static constexpr std::string_view keyword = "nan_energy_spring";
  struct Params {
    Real k = 0;  // N/m
  };
  static constexpr std::array<maille::ParamField<Params>, 1> fields{{
      {"k", "N/m", &Params::k, maille::Bound::positive},
  }};
  static Vec3 force(const Vec3& xa, const Vec3& xb, const Vec3&, const Vec3&, const Params& p) {
    return (xb - xa) * p.k;
  }
  static Real energy(const Vec3&, const Vec3&, const Params&) {
    return std::numeric_limits<Real>::quiet_NaN();
  }
  static Real stiffness(const Params& p) { return p.k; }
  static Real damping(const Params&) { return 0; }
};

TEST(CustomKind, NonFiniteEnergyIsABlowUpSaidInWords) {
  maille::Model m;
  const auto a = m.points.add(maille::PointKind::fixed, 1, {0, 0, 0});
  const auto b = m.points.add(maille::PointKind::free, 1, {0, -1, 0});
  m.links.pool<NanEnergySpring>().add({a, b}, {10});
  maille::SimulationSettings s;
  s.step = 1e-3;
  s.sample_every = 10;
  maille::Simulator sim(std::move(m), s);
  EXPECT_FALSE(sim.run_steps(100));
  ASSERT_TRUE(sim.blow_up());
  const std::string& why = sim.blow_up()->message;
  EXPECT_NE(why.find("the energy is not a number"), std::string::npos) << why;
  EXPECT_EQ(why.find("nan J"), std::string::npos) << why;
}

}  // namespace
