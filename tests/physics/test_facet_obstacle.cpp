// Facets by inverse dynamics against physics: nothing ends below a surface at any speed; on an
// incline a particle sticks while tan(theta) < beta and slides with g (sin - beta cos) beyond;
// the rebound height follows alpha^2 (alpha restitutes the normal velocity); particles thrown
// at closed meshes, many exactly at edges and vertices, never end inside (an independent
// winding-number test); a moving obstacle is met by the relative motion.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <random>

#include "maille/obstacle.hpp"
#include "test_support.hpp"

namespace {

using namespace maille;

Obstacle facet_obstacle(ShapeKind shape, const shapes::Affine& place, Real alpha, Real beta,
                        int resolution = 16) {
  Obstacle o;
  o.name = "o";
  o.method = ObstacleMethod::facets;
  o.shape = shape;
  o.place = place;
  o.alpha = alpha;
  o.beta = beta;
  o.resolution = resolution;
  return o;
}

void install(Model& m, const Obstacle& o) {
  m.stages.push_back({"obstacle:" + o.name, Phase::response,
                      [o](const Model& mm) { return make_obstacle_stage(mm, o); }});
}

std::uint64_t counter(const Simulator& sim, const std::string& name) {
  for (const auto& c : sim.profile().counters())
    if (c.name == name) return c.total;
  return 0;
}

// Generalised winding number (sum of solid angles, Van Oosterom and Strackee): about 1 inside a
// closed outward mesh, 0 outside. Independent of the stage's own inside test.
double winding(const TriMesh& mesh, const Vec3& p) {
  double w = 0;
  for (const auto& t : mesh.triangles) {
    const Vec3 a = mesh.vertices[t[0]] - p, b = mesh.vertices[t[1]] - p,
               c = mesh.vertices[t[2]] - p;
    const double la = norm(a), lb = norm(b), lc = norm(c);
    const double num = dot(a, cross(b, c));
    const double den = la * lb * lc + dot(a, b) * lc + dot(b, c) * la + dot(c, a) * lb;
    w += 2 * std::atan2(num, den);
  }
  return w / (4 * std::numbers::pi);
}

TEST(FacetObstacle, NothingEndsBelowAPlaneAtAnySpeed) {
  // A plane of 32 x 32 squares 1/16 m wide; particles fall at up to 8 facet widths per step,
  // straight and slanted, under every scheme that accepts a response stage.
  for (const char* scheme : {"leapfrog", "symplectic_euler", "explicit_euler"}) {
    Model m;
    std::vector<std::uint32_t> ids;
    for (int i = 0; i < 40; ++i) {
      const Real speed = Real(0.5) * Real(i * i);  // 0 to 760 m/s
      const Vec3 v{Real(0.3) * speed * Real(i % 3 - 1), -speed, Real(0.2) * speed};
      ids.push_back(m.points.add(PointKind::free, 0.01, {Real(-0.9 + 0.045 * i), 0.3, 0}, v));
    }
    install(m, facet_obstacle(shape_kind("plane"), shapes::Affine::from({}, {}, {2, 1, 2}), 0.5,
                              0.3, 32));
    Simulator sim(std::move(m), test::settings(1e-3, scheme));
    for (int step = 0; step < 400; ++step) {
      ASSERT_TRUE(sim.step());
      for (std::uint32_t p : ids) {
        const Vec3 x = sim.state().x()[p];
        if (std::abs(x.x) < 2 && std::abs(x.z) < 2) {  // over the plane
          ASSERT_GE(x.y, 0) << scheme << " particle " << p << " step " << step;
        }
      }
    }
  }
}

// On an incline of angle theta (a plane turned about z), a particle set on it at rest: it sticks
// when tan(theta) < beta; it slides with a = g (sin(theta) - beta cos(theta)) when tan > beta.
// Leapfrog integrates a constant acceleration exactly (s = a t^2 / 2 at whole steps), so the
// slide matches to rounding; the margins of 3 degrees on either side of atan(beta) are far from
// any numerical effect.
double slide_distance(Real theta_deg, Real alpha, Real beta, double seconds) {
  const Real theta = theta_deg * std::numbers::pi_v<Real> / 180;
  Model m;
  const Vec3 down{-std::cos(theta), -std::sin(theta), 0};  // along the incline, downhill
  const Vec3 normal{-std::sin(theta), std::cos(theta), 0};
  const Vec3 start = normal * Real(1e-7);
  const auto p = m.points.add(PointKind::free, 0.01, start);
  install(m,
          facet_obstacle(shape_kind("plane"),
                         shapes::Affine::from({}, {0, 0, theta_deg}, {50, 1, 50}), alpha, beta, 8));
  Simulator sim(std::move(m), test::settings(1e-3));
  EXPECT_TRUE(sim.run_steps(std::uint64_t(seconds / 1e-3)));
  const Vec3 x = sim.state().x()[p];
  EXPECT_GE(dot(x, normal), -1e-12) << "below the incline";
  return dot(x - start, down);
}

TEST(FacetObstacle, InclineSticksBelowTheFrictionAngleAndSlidesAbove) {
  const double g = 9.81, t = 1.0;
  for (Real alpha : {Real(0), Real(0.5)})
    for (Real beta : {Real(0.2), Real(0.5), Real(0.8)}) {
      const Real critical = std::atan(beta) * 180 / std::numbers::pi_v<Real>;
      EXPECT_LT(std::abs(slide_distance(critical - 3, alpha, beta, t)), 1e-6)
          << "alpha " << alpha << " beta " << beta << ": should stick";
      const double th = (critical + 3) * std::numbers::pi / 180;
      const double expected = 0.5 * g * (std::sin(th) - beta * std::cos(th)) * t * t;
      EXPECT_NEAR(slide_distance(critical + 3, alpha, beta, t), expected, 0.02 * expected)
          << "alpha " << alpha << " beta " << beta << ": should slide";
    }
}

TEST(FacetObstacle, WithoutFrictionItSlidesWithGSinTheta) {
  for (Real theta : {Real(10), Real(30), Real(60)}) {
    const double th = theta * std::numbers::pi / 180;
    const double expected = 0.5 * 9.81 * std::sin(th);
    EXPECT_NEAR(slide_distance(theta, 0, 0, 1.0), expected, 1e-3 * expected) << theta;
  }
}

// Dropped from H onto a level facet, the particle leaves with -alpha times its normal velocity,
// so it climbs back to alpha^2 H. The step (1e-4 s) makes the impact time uncertain by one
// step: the apex is within 2 g h sqrt(2 g H) / g of the law, about 0.2 % of H here.
TEST(FacetObstacle, ReboundFollowsTheAlphaLaw) {
  const double H = 0.5;
  for (Real alpha : {Real(0.3), Real(0.6), Real(0.9)}) {
    Model m;
    const auto p = m.points.add(PointKind::free, 0.01, {0, Real(H), 0});
    install(m, facet_obstacle(shape_kind("plane"), {}, alpha, 0.3, 4));
    Simulator sim(std::move(m), test::settings(1e-4));
    bool bounced = false;
    double apex = 0, last_y = H;
    for (int i = 0; i < 30000; ++i) {
      ASSERT_TRUE(sim.step());
      const double y = sim.state().x()[p].y;
      if (!bounced && y > last_y) bounced = true;
      if (bounced) {
        if (y < last_y) break;  // past the apex
        apex = y;
      }
      last_y = y;
    }
    EXPECT_NEAR(apex, alpha * alpha * H, 0.01 * H) << "alpha " << alpha;
  }
}

// 10^5 particles thrown at a closed mesh from every direction, a third aimed exactly at its
// vertices, a third at edge midpoints, at speeds up to several facets per step: none ends
// inside (winding number < 1/2), and each kept moving toward the mesh long enough to hit it.
void throw_at(const TriMesh& mesh, const Obstacle& o, int count, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<Real> uni(-1, 1);
  std::vector<Vec3> targets;
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
    const auto& tri = mesh.triangles[t];
    const Vec3 a = mesh.vertices[tri[0]], b = mesh.vertices[tri[1]], c = mesh.vertices[tri[2]];
    targets.push_back(a);
    targets.push_back((a + b) / 2);
    targets.push_back((a + b + c) / 3);
  }
  Model m;
  m.fields.gravity = {0, 0, 0};
  const Real h = 1e-3;
  for (int i = 0; i < count; ++i) {
    Vec3 dir{uni(rng), uni(rng), uni(rng)};
    while (norm(dir) < 0.1) dir = {uni(rng), uni(rng), uni(rng)};
    dir = dir / norm(dir);
    const Vec3 target = o.place.to_world(targets[i % targets.size()]);
    const Real speed = Real(20) * (1 + Real(i % 7) * 10);  // 0.02 to 1.2 m per step
    const Real lead = speed * h * Real(3 + i % 5);         // a few steps away
    m.points.add(PointKind::free, 0.01, target + dir * (lead + Real(0.05)), dir * -speed);
  }
  install(m, o);
  Simulator sim(std::move(m), test::settings(h));
  ASSERT_TRUE(sim.run_steps(40));
  int inside = 0;
  for (std::uint32_t p = 0; p < sim.state().size(); ++p)
    inside += winding(mesh, o.place.to_canonical(sim.state().x()[p])) > 0.5;
  EXPECT_EQ(inside, 0);
  EXPECT_GT(counter(sim, "obstacle_o_hits"), std::uint64_t(count) / 2);
  ::testing::Test::RecordProperty("facet_leaks_pushed_out",
                                  std::to_string(counter(sim, "obstacle_o_facet_leaks")));
}

TEST(FacetObstacle, ThrownParticlesNeverEndInsideACube) {
  const Obstacle o = facet_obstacle(
      shape_kind("cube"), shapes::Affine::from({0.1, 0.2, 0}, {20, 30, 40}, {0.3, 0.2, 0.25}), 0.5,
      0.3, 4);
  throw_at(obstacle_mesh(o), o, 100000, 1);
}

TEST(FacetObstacle, ThrownParticlesNeverEndInsideAnIcosphere) {
  Obstacle o =
      facet_obstacle(shape_kind("sphere"), shapes::Affine::from({}, {}, {0.3, 0.3, 0.3}), 0.5, 0.3);
  o.mesh = std::make_shared<const TriMesh>(icosphere(2));
  throw_at(*o.mesh, o, 100000, 2);
}

TEST(FacetObstacle, ThrownParticlesNeverEndInsideTheExampleRock) {
  Obstacle o = facet_obstacle(shape_kind("sphere"),
                              shapes::Affine::from({}, {0, 45, 0}, {0.4, 0.4, 0.4}), 0.2, 0.5);
  o.mesh =
      std::make_shared<const TriMesh>(read_mesh(MAILLE_SOURCE_DIR "/examples/models/rock.obj"));
  throw_at(*o.mesh, o, 10000, 3);
}

// Every tessellated canonical shape (under a non-uniform scale and a rotation), particles
// thrown from all sides at up to several facets per step: none ends inside.
TEST(FacetObstacle, ThrownParticlesNeverEndInsideAnyTessellatedShape) {
  for (ShapeKind shape : {shape_kind("sphere"), shape_kind("cube"), shape_kind("cylinder"),
                          shape_kind("cone"), shape_kind("torus"), shape_kind("capsule")}) {
    const Obstacle o = facet_obstacle(
        shape, shapes::Affine::from({0, 0.1, 0}, {10, 20, 30}, {0.3, 0.2, 0.25}), 0.5, 0.3, 24);
    SCOPED_TRACE(std::string(to_string(shape)));
    throw_at(obstacle_mesh(o), o, 5000, 10 + static_cast<int>(shape));
  }
}

// A cube turning at 2 turns per second sweeps through particles at rest around it: met by the
// relative motion, none ends inside.
TEST(FacetObstacle, ARotatingCubeSweepsParticlesOut) {
  Obstacle o = facet_obstacle(shape_kind("cube"), shapes::Affine::from({}, {}, {0.3, 0.1, 0.1}),
                              0.5, 0.3, 4);
  o.motion.kind = ObstacleMotion::Kind::rotate;
  o.motion.frequency = 2;
  Model m;
  m.fields.gravity = {0, 0, 0};
  const TriMesh mesh = obstacle_mesh(o);
  for (int i = 0; i < 400; ++i) {  // around the cube's sweep, none inside it at the start
    const Real a = Real(i) * Real(0.0157), r = Real(0.15) + Real(i % 10) * Real(0.015);
    const Vec3 x{r * std::cos(a), Real(0.05) * Real(i % 3 - 1), r * std::sin(a)};
    if (winding(mesh, o.place.to_canonical(x)) < 0.5) m.points.add(PointKind::free, 0.01, x);
  }
  ASSERT_GT(m.points.size(), 250u);
  install(m, o);
  Simulator sim(std::move(m), test::settings(1e-4));
  for (int k = 0; k < 10; ++k) {
    ASSERT_TRUE(sim.run_steps(250));
    const shapes::Affine now = o.motion.at(o.place, sim.state().time);
    for (std::uint32_t p = 0; p < sim.state().size(); ++p)
      ASSERT_LT(winding(mesh, now.to_canonical(sim.state().x()[p])), 0.5) << p << " at " << k;
  }
}

// A scene that starts with particles inside a closed mesh (deep, near a face, near a corner):
// the first step finds each by its nearest facet, puts it on the surface and counts it.
TEST(FacetObstacle, ParticlesStartingInsideArePutOutOnTheFirstStep) {
  const Obstacle o =
      facet_obstacle(shape_kind("cube"),
                     shapes::Affine::from({0, 0.3, 0}, {30, 20, 10}, {0.25, 0.25, 0.25}), 0, 0, 4);
  Model m;
  m.fields.gravity = {0, 0, 0};
  // The centre, near a face, near a corner (canonical coordinates).
  for (const Vec3& local : {Vec3{0, 0, 0}, Vec3{0.9, 0.1, 0}, Vec3{0.95, 0.95, 0.95}})
    m.points.add(PointKind::free, 0.01, o.place.to_world(local));
  install(m, o);
  Simulator sim(std::move(m), test::settings(1e-4));
  ASSERT_TRUE(sim.step());
  EXPECT_EQ(counter(sim, "obstacle_o_facet_leaks"), 3u);
  for (std::uint32_t p = 0; p < 3; ++p) {
    const Vec3 c = o.place.to_canonical(sim.state().x()[p]);
    EXPECT_GE(std::max({std::abs(c.x), std::abs(c.y), std::abs(c.z)}), 1) << p;
  }
}

TEST(FacetObstacle, SchemesThatEvaluateForcesTwiceRefuseIt) {
  Model m;
  m.points.add(PointKind::free, 0.01, {0, 1, 0});
  install(m, facet_obstacle(shape_kind("plane"), {}, 0.5, 0.3, 4));
  try {
    Simulator sim(std::move(m), test::settings(1e-3, "rk4"));
    FAIL() << "rk4 accepted a response stage";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("rewrites forces and velocities after the fact"),
              std::string::npos);
  }
}

}  // namespace
