// Self-collision friction inside the implicit solve: the stage's point-point contacts
// carry their Coulomb friction into the solve lagged (normal and normal force of the step's
// start held, smoothed law with its tangent block: src/collision/self/self_contact_link.hpp).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <numbers>

#include "maille/builders.hpp"
#include "maille/link_loops.hpp"
#include "maille/obstacle.hpp"
#include "maille/self_collision.hpp"
#include "maille/simulator.hpp"
#include "test_support.hpp"

namespace maille {
namespace {

// Two free cloths on a plane, under gravity tilted by theta about z (the same as a plane tilted
// by theta): a 0.6 m cloth (21 x 21, spacing 3 cm, 0.1 kg) held on the plane by its friction
// (mu = 2: it sticks), and a 0.18 m cloth (7 x 7, 0.02 kg) lying on it, above its cells'
// centres, colliding by self-collision (radius 3 cm, 1000 N/m, friction mu): the top cloth's
// mean displacement along the slope after `duration`, relative to the bottom cloth's.
double slid_on_a_tilted_cloth(double theta_deg, Real mu, const char* integrator, double h,
                              double duration, Primitive primitive = Primitive::points) {
  Model m;
  FlagParams floor;
  floor.nx = floor.ny = 21;
  floor.width = floor.height = 0.6;
  floor.mass = 0.1;
  floor.origin = {-0.3, 0.001, -0.3};
  floor.up = {0, 0, 1};
  floor.fixed = FlagFixed::none;
  build_flag(m, floor, "floor");
  FlagParams top;
  top.nx = top.ny = 7;
  top.width = top.height = 0.18;
  top.mass = 0.02;
  top.material = {200, Real(0.02)};
  top.origin = {-0.09 + 0.015, 0.026, -0.09 + 0.015};  // above the floor's cell centres
  top.up = {0, 0, 1};
  top.fixed = FlagFixed::none;
  build_flag(m, top, "top");
  const double theta = theta_deg * std::numbers::pi / 180;
  m.fields.gravity = {Real(9.81 * std::sin(theta)), Real(-9.81 * std::cos(theta)), 0};
  SelfCollisionSettings s;
  s.groups = {"floor", "top"};
  s.radius = 0.03;
  s.stiffness = 1000;
  s.damping = 0.2;
  s.friction = mu;
  s.primitive = primitive;
  m.stages.push_back({"self_collision", Phase::forces,
                      [s](const Model& mm) { return make_self_collision_stage(mm, s); }});
  Obstacle plane;
  plane.name = "plane";
  plane.method = ObstacleMethod::geometric;
  plane.shape = shape_kind("plane");
  plane.stiffness = 5000;
  plane.damping = 1;
  plane.friction = 2;
  m.stages.push_back({"obstacle:plane", Phase::forces,
                      [plane](const Model& mm) { return make_obstacle_stage(mm, plane); }});
  const std::uint32_t first = 21 * 21, count = m.points.size() - first;
  SimulationSettings settings = test::settings(h, integrator);
  settings.implicit.solver = ImplicitSolver::vbd;
  Simulator sim(m, settings);
  EXPECT_TRUE(sim.run_steps(static_cast<std::uint64_t>(std::llround(duration / h))));
  double top_dx = 0, floor_dx = 0;
  for (std::uint32_t i = 0; i < sim.state().size(); ++i)
    (i < first ? floor_dx : top_dx) +=
        double(sim.state().x()[i].x - m.points.initial_position[i].x);
  return top_dx / count - floor_dx / first;
}

// At h = 1/60 s with VBD (10 sweeps). The top cloth's points rest in the dimples between the lower
// cloth's particles, whose walls hold it up to about 45 degrees without friction: leapfrog at
// 1e-4 s moves it 83 um at 30 degrees and slides it 0.65 m at 45 and 2.55 m at 60 in 1 s. (This
// test asked for a slide at 30 degrees before the coarse correction: VBD's sweeps alone, short
// of convergence, let the points climb out; they slide 0.31 m there still, the coarse correction
// leaving points in two-body contacts to the sweeps.) At 60 degrees without friction it slides
// (0.91 m); with mu = 2 > tan 60 = 1.73 it sticks: at most the creep of the smoothed law and the
// settling of the contacts (3.9 mm; leapfrog 4.7 mm). With mu = 0.8 it moves at most 5 mm at 30
// degrees and 1 mm at 10. With the friction explicit (the force of the step's start, as before
// this solve took it) the runs at 30 and 10 degrees with mu = 0.8 slid 0.94 m and 0.19 m: a force
// taken at the start of a 1/60 s step reverses the sliding it should stop.
TEST(SelfFriction, ClothOnClothSticksAtLargeStepsBelowTheFrictionAngle) {
  const double h = 1.0 / 60;
  EXPECT_GT(slid_on_a_tilted_cloth(60, 0, "implicit_euler", h, 1.0), 0.1);
  EXPECT_LT(std::abs(slid_on_a_tilted_cloth(60, 2, "implicit_euler", h, 1.0)), 1e-2);
  EXPECT_LT(std::abs(slid_on_a_tilted_cloth(30, Real(0.8), "implicit_euler", h, 1.0)), 5e-3);
  EXPECT_LT(std::abs(slid_on_a_tilted_cloth(10, Real(0.8), "implicit_euler", h, 1.0)), 1e-3);
}

// The same with primitive = "triangles" (the point-triangle contacts' friction lagged too,
// TriangleContactTerms::lag): the faces are smooth, so without friction the top cloth slides
// already at 10 degrees (0.29 m in 1 s); with mu = 0.8 it stays within 1.8 mm at 10 degrees and
// 5.2 mm at 30. With the point-triangle friction explicit the same runs moved 4.4 cm (backwards:
// the start-of-step force overshoots) and 0.13 m.
TEST(SelfFriction, ClothOnClothSticksOnTrianglesAtLargeSteps) {
  const double h = 1.0 / 60;
  const Primitive tri = Primitive::triangles;
  EXPECT_GT(slid_on_a_tilted_cloth(10, 0, "implicit_euler", h, 1.0, tri), 0.1);
  EXPECT_LT(std::abs(slid_on_a_tilted_cloth(10, Real(0.8), "implicit_euler", h, 1.0, tri)), 5e-3);
  EXPECT_LT(std::abs(slid_on_a_tilted_cloth(30, Real(0.8), "implicit_euler", h, 1.0, tri)), 1e-2);
}

// The contact set's pairs at the step's start give the explicit pass's forces (normal law and
// friction): an implicit step that starts at rest against a contact starts from the force an
// explicit scheme would apply, the same law evaluated over the set found at radius + margin.
TEST(SelfFriction, LaggedTermsAtTheStepStartAreTheStagesForces) {
  Model m;
  FlagParams a;
  a.nx = a.ny = 3;
  a.width = a.height = 0.04;
  a.up = {0, 0, 1};
  a.fixed = FlagFixed::none;
  build_flag(m, a, "a");
  FlagParams b = a;
  b.origin = {0.004, 0.015, 0.007};
  build_flag(m, b, "b");
  State st(m.points.size());
  for (std::size_t i = 0; i < st.size(); ++i) {
    st.x()[i] = m.points.initial_position[i];
    st.v()[i] = {Real(0.3 * std::sin(double(i))), Real(0.1 * std::cos(3.0 * double(i))),
                 Real(-0.2 * std::sin(2.0 * double(i)))};
  }
  SelfCollisionSettings s;
  s.groups = {"a", "b"};
  s.radius = 0.03;
  s.stiffness = 800;
  s.damping = 0.3;
  s.friction = 0.6;
  s.exclusion = Exclusion::none;
  auto stage = make_self_collision_stage(m, s);
  StageContext ctx;
  ctx.h = 1.0 / 60;
  ctx.jacobians = true;
  stage->apply(m, st, ctx);  // the explicit pass: the stage's forces into st.f()
  State found = st;
  std::fill(found.f().begin(), found.f().end(), Vec3{});
  ContactSet set;
  stage->find_contacts(m, found, ctx, set);  // the solve's: the set, no force
  for (const Vec3& f : found.f()) ASSERT_EQ(f, Vec3{});
  ASSERT_EQ(set.pairs().size(), 1u);
  const LinkPoolBase* pool = set.pairs()[0];
  ASSERT_GT(pool->size(), 0u);
  std::vector<Vec3> f(st.size());
  LinkCounters counters;
  maille::accumulate_forces(*pool, st.x().data(), st.v().data(), f.data(), counters);
  Real largest = 0;
  for (std::size_t i = 0; i < st.size(); ++i) largest = std::max(largest, norm(st.f()[i]));
  ASSERT_GT(largest, 0);
  for (std::size_t i = 0; i < st.size(); ++i)
    EXPECT_LT(norm(f[i] - st.f()[i]), 1e-12 * largest) << "point " << i;
}

}  // namespace
}  // namespace maille
