// Each link kind's force law alone: Newton's third law, force = -grad energy, the conditional
// threshold, the axial damper.
#include <gtest/gtest.h>

#include "maille/links/conditional.hpp"
#include "test_support.hpp"

namespace maille {
namespace {

// Central differences of the energy with step 1e-6 have O(1e-12) truncation error and O(1e-10)
// rounding error relative to forces of order 1 N: 1e-6 relative is a safe, discriminating bound.
template <class K>
void expect_force_is_minus_energy_gradient(const typename K::Params& p, Vec3 xa, Vec3 xb) {
  const Vec3 f = K::force(xa, xb, {}, {}, p);
  const Real h = 1e-6;
  for (int axis = 0; axis < 3; ++axis) {
    Vec3 dp{}, dm{};
    (axis == 0 ? dp.x : axis == 1 ? dp.y : dp.z) = h;
    dm = -dp;
    const Real grad = (K::energy(xa + dp, xb, p) - K::energy(xa + dm, xb, p)) / (2 * h);
    EXPECT_NEAR(f[axis], -grad, 1e-6 * (1 + norm(f))) << K::keyword << " axis " << axis;
  }
}

TEST(Links, SpringForceIsMinusEnergyGradient) {
  expect_force_is_minus_energy_gradient<Spring>({150, 0.8}, {0.1, 0.2, -0.3}, {0.9, 0.5, 0.4});
  expect_force_is_minus_energy_gradient<SpringDamper>({150, 1.8, 3}, {0.1, 0.2, -0.3},
                                                      {0.9, 0.5, 0.4});
  expect_force_is_minus_energy_gradient<ConditionalSpringDamper>({150, 3, 1.5, 1.5},
                                                                 {0.1, 0.2, -0.3}, {0.9, 0.5, 0.4});
}

TEST(Links, SpringPullsWhenStretchedPushesWhenCompressed) {
  const Spring::Params p{100, 1};
  EXPECT_NEAR(Spring::force({0, 0, 0}, {1.5, 0, 0}, {}, {}, p).x, 50, 1e-12);
  EXPECT_NEAR(Spring::force({0, 0, 0}, {0.5, 0, 0}, {}, {}, p).x, -50, 1e-12);
  EXPECT_EQ(Spring::force({0, 0, 0}, {0, 0, 0}, {}, {}, p), Vec3{});  // coincident: no direction
}

// The damper is axial: only the relative velocity along the link is resisted.
TEST(Links, DamperIsAxial) {
  const Damper::Params p{2};
  const Vec3 along = Damper::force({0, 0, 0}, {1, 0, 0}, {0, 0, 0}, {3, 0, 0}, p);
  EXPECT_NEAR(along.x, 6, 1e-12);  // resists separation: pulls a toward b
  const Vec3 across = Damper::force({0, 0, 0}, {1, 0, 0}, {0, 0, 0}, {0, 5, 0}, p);
  EXPECT_LT(norm(across), 1e-12);
}

TEST(Links, ConditionalSilentBeyondThresholdActiveInside) {
  const ConditionalSpringDamper::Params p{1000, 2, 0.1, 0.1};
  const Vec3 a{0, 0, 0};
  EXPECT_FALSE(ConditionalSpringDamper::is_active(a, {0.1001, 0, 0}, p));
  EXPECT_EQ(ConditionalSpringDamper::force(a, {0.1001, 0, 0}, {}, {-1, 0, 0}, p), Vec3{});
  EXPECT_EQ(ConditionalSpringDamper::energy(a, {0.15, 0, 0}, p), 0);
  ASSERT_TRUE(ConditionalSpringDamper::is_active(a, {0.08, 0, 0}, p));
  // Inside: pushes a away from b with k (s - d), plus the damper on the closing speed.
  const Vec3 f = ConditionalSpringDamper::force(a, {0.08, 0, 0}, {}, {-1, 0, 0}, p);
  EXPECT_NEAR(f.x, -(1000 * 0.02) - 2 * 1, 1e-9);
}

// Two masses flying at each other through a conditional link: no force until they are closer
// than the threshold, then a repulsion that turns them back; the active-link counter says when.
TEST(Links, ConditionalLinkBouncesTwoMasses) {
  Model m;
  m.fields.gravity = {0, 0, 0};
  const auto a = m.points.add(PointKind::free, 1, {-0.5, 0, 0}, {1, 0, 0});
  const auto b = m.points.add(PointKind::free, 1, {0.5, 0, 0}, {-1, 0, 0});
  m.links.pool<ConditionalSpringDamper>().add({a, b}, {1e4, 0, 0.2, 0.2});
  Simulator sim(std::move(m), test::settings(1e-4));
  ASSERT_EQ(sim.profile().counters()[0].name, "active_conditional_links");
  // Until the gap closes to 0.2 m (t = 0.4 s) they fly freely.
  sim.run_steps(3900);
  EXPECT_NEAR(sim.state().v()[a].x, 1, 1e-12);
  EXPECT_EQ(sim.profile().counters()[0].last, 0u);
  sim.run_steps(200);
  EXPECT_EQ(sim.profile().counters()[0].last, 1u);
  sim.run_steps(5000);
  // Elastic bounce (no damping): they leave at the speed they came, within the leapfrog error.
  EXPECT_NEAR(sim.state().v()[a].x, -1, 1e-3);
  EXPECT_NEAR(sim.state().v()[b].x, 1, 1e-3);
  EXPECT_GT(norm(sim.state().x()[b] - sim.state().x()[a]), 0.2);
}

}  // namespace
}  // namespace maille
