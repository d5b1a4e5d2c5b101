// Geometric obstacles against physics: a particle resting on each canonical shape (uniform scale)
// settles exactly m g / k below its top (leapfrog's static equilibrium is exact; damping settles
// it); under a non-uniform scale the "world" variant pushes along the world normal while the
// canonical force mapped through M_d leans off it; a key the method does not use is an error.
#include <gtest/gtest.h>

#include <cmath>

#include "maille/obstacle.hpp"
#include "maille/scene.hpp"
#include "test_support.hpp"

namespace {

using namespace maille;

double resting_height(ShapeKind shape, const Vec3& above, Real scale) {
  Model m;
  const auto bead = m.points.add(PointKind::free, 0.01, above);
  m.groups.push_back({"bead", "points", bead, 1});
  Obstacle o;
  o.shape = shape;
  o.place = shapes::Affine::from({0, 1, 0}, {0, 0, 0}, {scale, scale, scale});
  o.stiffness = 400;
  o.damping = 0.3;
  m.stages.push_back({"obstacle:o", Phase::forces,
                      [o](const Model& mm) { return make_geometric_obstacle_stage(mm, o); }});
  Simulator sim(std::move(m), test::settings(2e-4));
  EXPECT_TRUE(sim.run_steps(40000));
  return sim.state().x()[bead].y;
}

TEST(GeometricObstacle, ARestingParticleSinksMgOverK) {
  const Real s = 0.3, sink = 0.01 * 9.81 / 400;
  struct Case {
    ShapeKind shape;
    Vec3 above;  // start, just over the top
    double top;  // world height of the surface under it
  };
  const Case cases[] = {
      {shape_kind("sphere"), {0, 1.35, 0}, 1.3},  // on the axis: at the pole
      {shape_kind("cube"), {0.1, 1.35, -0.1}, 1.3}, {shape_kind("cylinder"), {0.1, 1.35, 0.1}, 1.3},
      {shape_kind("cone"), {0.02, 1.35, 0}, 1.3},   {shape_kind("torus"), {0.3, 1.15, 0}, 1.09},
      {shape_kind("capsule"), {0, 1.65, 0}, 1.6},   {shape_kind("plane"), {0.4, 1.05, 0.4}, 1.0}};
  for (const Case& c : cases) {
    const double y = resting_height(c.shape, c.above, s);
    EXPECT_NEAR(y, c.top - sink, 1e-6) << to_string(c.shape);
  }
}

// An ellipsoid (sphere scaled 0.6, 0.3, 0.3): at a point inside near the surface off the axes,
// the world variant's force is along the ellipsoid's normal (the gradient of x^2/a^2 + ...);
// the canonical force mapped through M_d leans off it (measured, and reported by the study).
TEST(GeometricObstacle, WorldNormalVariantUnderNonUniformScale) {
  auto force = [](bool world) {
    Model m;
    const Vec3 surface{Real(0.6 * std::cos(0.6)), Real(0.3 * std::sin(0.6)), 0};
    const Vec3 p = surface * Real(0.98);
    const auto bead = m.points.add(PointKind::free, 0.01, p);
    m.groups.push_back({"bead", "points", bead, 1});
    Obstacle o;
    o.place = shapes::Affine::from({0, 0, 0}, {0, 0, 0}, {0.6, 0.3, 0.3});
    o.damping = 0;
    o.world_normal = world;
    auto stage = make_geometric_obstacle_stage(m, o);
    State s(1);
    s.x()[0] = p;
    stage->apply(m, s, StageContext{});
    return std::pair{s.f()[0], Vec3{p.x / Real(0.36), p.y / Real(0.09), 0}};
  };
  const auto [fw, grad] = force(true);
  const Vec3 n = grad / norm(grad);
  EXPECT_NEAR(dot(fw / norm(fw), n), 1, 1e-12);
  const auto [fc, unused] = force(false);
  const double lean = std::acos(std::min(1.0, double(dot(fc / norm(fc), n))));
  EXPECT_GT(lean, 0.05);  // radians: the canonical mapping is off the normal here
}

TEST(GeometricObstacle, SceneTableChecksKeysAgainstTheMethod) {
  auto scene = [](const std::string& extra) {
    return parse_scene(
        "[[mass]]\nname = \"bead\"\nmass = 0.01\nposition = [0.0, 2.0, 0.0]\n"
        "[[obstacle]]\nname = \"ball\"\nshape = \"sphere\"\n" +
            extra,
        "o.toml", LinkKindRegistry::with_builtins(), StageRegistry::with_builtins());
  };
  auto ok = scene("scale = [0.3, 0.3, 0.3]\nstiffness = 500.0\n");
  ASSERT_TRUE(ok) << ok.error().to_string();
  ASSERT_EQ(ok->model.stages.size(), 1u);
  EXPECT_EQ(ok->model.stages[0].name, "obstacle:ball");
  auto threshold = scene("threshold = 0.02\n");
  ASSERT_FALSE(threshold);
  EXPECT_NE(threshold.error().key.find("threshold"), std::string::npos);
  EXPECT_NE(threshold.error().message.find("geometric"), std::string::npos);
  auto tube = scene("tube = 0.3\n");
  ASSERT_FALSE(tube);
  auto facets = scene("method = \"facets\"\nalpha = 0.5\nbeta = 0.2\n");
  ASSERT_TRUE(facets) << facets.error().to_string();
  EXPECT_EQ(facets->model.stages[0].phase, Phase::response);
  auto spring_on_facets = scene("method = \"facets\"\nstiffness = 10.0\n");
  ASSERT_FALSE(spring_on_facets);
  EXPECT_NE(spring_on_facets.error().key.find("stiffness"), std::string::npos);
  EXPECT_NE(spring_on_facets.error().message.find("\"facets\""), std::string::npos);
  auto alpha_on_conditional = scene("method = \"conditional\"\nalpha = 0.5\n");
  ASSERT_FALSE(alpha_on_conditional);
  EXPECT_NE(alpha_on_conditional.error().message.find("\"conditional\""), std::string::npos);
  auto conditional = scene("method = \"conditional\"\nthreshold = 0.05\nscale = [0.3, 0.3, 0.3]\n");
  ASSERT_TRUE(conditional) << conditional.error().to_string();
}

// The bricks: a [[geometric_point]] (a cube turned 45 degrees about y, scaled 0.2) and
// geometric_contact links to a bead and to a group. Resting on the top face, each bead sinks
// m g / k below it, like the obstacle (the same law), and the stage counts its contacts.
TEST(GeometricObstacle, GeometricPointAndContactBricks) {
  const std::string text =
      "[simulation]\nstep = 2e-4\n"
      "[[mass]]\nname = \"bead\"\nmass = 0.01\nposition = [0.0, 1.21, 0.0]\n"
      "[[mass]]\nname = \"other\"\nmass = 0.02\nposition = [0.05, 1.21, 0.0]\n"
      "[[geometric_point]]\nname = \"box\"\nshape = \"cube\"\nposition = [0.0, 1.0, 0.0]\n"
      "rotation = [0.0, 45.0, 0.0]\nscale = [0.2, 0.2, 0.2]\n"
      "[[link]]\nkind = \"geometric_contact\"\na = \"box\"\nb = \"bead\"\n"
      "stiffness = 400.0\ndamping = 0.3\n"
      "[[link]]\nkind = \"geometric_contact\"\na = \"box\"\nb = \"other\"\n"
      "stiffness = 400.0\ndamping = 0.3\n";
  auto scene = parse_scene(text, "bricks.toml", LinkKindRegistry::with_builtins(),
                           StageRegistry::with_builtins());
  ASSERT_TRUE(scene) << scene.error().to_string();
  ASSERT_EQ(scene->model.geometric_points.size(), 1u);
  scene->settings.threads = 1;
  Simulator sim(std::move(scene->model), scene->settings);
  ASSERT_TRUE(sim.run_steps(40000));
  EXPECT_NEAR(sim.state().x()[0].y, 1.2 - 0.01 * 9.81 / 400, 1e-6);
  EXPECT_NEAR(sim.state().x()[1].y, 1.2 - 0.02 * 9.81 / 400, 1e-6);
  std::uint64_t active = 0;
  for (const auto& c : sim.profile().counters())
    if (c.name == "geometric_contacts_active") active = c.last;
  EXPECT_EQ(active, 2u);
}

}  // namespace
