// Geometric obstacles on the GPU backend (src/gpu/gpu_obstacle.*) against the CPU stage: the
// contact forces of every shape on the same input, whole runs of a cloth falling on a sphere,
// a box, a plane with friction and a moving obstacle, a point resting on a plane at m g / k, and
// the refusal of the other methods.
//
// Tolerances. Forces: the GPU evaluates the shared law (obstacle_laws.glsl) in float on x and
// v stored in float, with the placement rounded to float. Every one of those roundings moves
// the canonical point c = M_i (x - t) by a few eps of |M_i| (|x| + |t|) and the shape's own
// arithmetic by a few eps of |c| + 1 canonical units: all of it is the law evaluated at an input
// perturbed by at most dx = 16 eps kappa (X + T + 1) in the world (kappa = |M_d| |M_i|, the
// placement's condition number; X, T: the largest coordinate and |t|; 16: a few roundings per
// stage, doubled), and likewise at a velocity perturbed by dv = 16 eps kappa (V + |w| (X + T))
// (w the obstacle's spin), plus the final rounding of the force, 8 eps |F|. So the GPU's force
// lies within the CPU law's spread over such perturbations: measured at x +- 2 dx and
// v +- 2 dv along each axis (2 > sqrt(3): any boundary within dx, such as a cube's diagonal
// or the surface, is crossed along some axis), the spread times 3 (a perturbation splits into
// three axis parts) bounds what the GPU may differ by. This needs no list of each shape's
// discontinuities: near one, the spread holds the jump.
// Runs: as test_gpu_runs.cpp, the GPU may drift from the CPU by 4 times what float storage alone
// does to the CPU's trajectory (the CPU run rounded to float after every step).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <random>
#include <string>
#include <vector>

#include "gpu/gpu_test_support.hpp"
#include "maille/backend.hpp"
#include "maille/gpu.hpp"
#include "maille/link_registry.hpp"
#include "maille/obstacle.hpp"
#include "maille/scene.hpp"
#include "maille/simulator.hpp"
#include "maille/stage_registry.hpp"

namespace maille {
namespace {

constexpr double kEps = test::kFloatEps;
using GpuObstacles = test::GpuTest;

// A placement that rotates, scales unevenly and moves (rotate about a tilted axis).
Obstacle tilted(ShapeKind shape, bool world_normal, bool moving) {
  Obstacle o;
  o.name = "o";
  o.shape = shape;
  if (shape == shape_kind("cone")) o.shape_parameter = Real(0.4);    // top
  if (shape == shape_kind("torus")) o.shape_parameter = Real(0.35);  // tube
  o.place = shapes::Affine::from({0.1, 0.2, -0.1}, {20, 35, -10}, {0.5, 0.3, 0.4});
  o.stiffness = 3000;
  o.damping = 2;
  o.friction = Real(0.4);
  o.world_normal = world_normal;
  if (moving) {
    o.motion.kind = ObstacleMotion::Kind::rotate;
    o.motion.axis = {0.3, 1, 0.2};
    o.motion.center = {0.1, 0.2, -0.1};
    o.motion.frequency = Real(0.7);
  }
  return o;
}

// The CPU stage's forces at s (time t).
std::vector<Vec3> cpu_forces(const Model& m, Stage& stage, State s, double t) {
  std::fill(s.f().begin(), s.f().end(), Vec3{});
  StageContext ctx;
  ctx.t = t;
  stage.apply(m, s, ctx);
  return {s.f().begin(), s.f().end()};
}

// n free points scattered about the obstacle with random velocities; no gravity, no links: the
// GPU's f is the stage's force alone.
double expect_forces_match(const Obstacle& o, const char* what) {
  Model m;
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> at(-0.7, 0.7);
  std::normal_distribution<double> speed(0, 0.8);
  const std::uint32_t n = 3000;
  for (std::uint32_t i = 0; i < n; ++i)
    m.points.add(PointKind::free, Real(0.01),
                 o.place.translation + Vec3{Real(at(rng)), Real(at(rng)), Real(at(rng))});
  m.groups.push_back({"all", "points", 0, n});
  m.fields.gravity = {};
  m.fields.air_drag = 0;
  m.prepare();
  State s(n);
  for (std::uint32_t i = 0; i < n; ++i) {
    s.x()[i] = m.points.initial_position[i];
    s.v()[i] = {Real(speed(rng)), Real(speed(rng)), Real(speed(rng))};
  }
  test::round_to_float(s);  // the GPU's input is the CPU's
  const double t = 0.3;
  auto stage = make_obstacle_stage(m, o);
  const std::vector<Vec3> cpu = cpu_forces(m, *stage, s, t);

  auto b = BackendRegistry::global().find("gpu")->make(BackendOptions{});
  const Stage* stages[] = {stage.get()};
  b->load(m, s, stages);
  b->evaluate(m, t);
  State out(n);
  b->download(out);

  // The perturbations' sizes (header); Frobenius norms bound |M_d| and |M_i| from above.
  auto frobenius = [](const Mat3& a) {
    double f2 = 0;
    for (const auto& row : a.m)
      for (const Real e : row) f2 += double(e) * e;
    return std::sqrt(f2);
  };
  const double kappa = frobenius(o.place.direct) * frobenius(o.place.inverse),
               X = test::max_abs(s.x()), V = test::max_norm(s.v()), T = norm(o.place.translation),
               w = o.motion.moves() ? norm(o.motion.twist(t).spin) : 0;
  const double dx = 16 * kEps * kappa * (X + T + 1), dv = 16 * kEps * kappa * (V + w * (X + T));
  std::vector<double> spread(n, 0);
  for (int axis = 0; axis < 6; ++axis)
    for (const bool on_x : {true, false}) {
      State p = s;
      Vec3 e{};
      (axis % 3 == 0 ? e.x : axis % 3 == 1 ? e.y : e.z) = Real(axis < 3 ? 2 : -2);
      for (std::uint32_t i = 0; i < n; ++i)
        (on_x ? p.x()[i] : p.v()[i]) += e * Real(on_x ? dx : dv);
      const std::vector<Vec3> moved = cpu_forces(m, *stage, p, t);
      for (std::uint32_t i = 0; i < n; ++i)
        spread[i] = std::max(spread[i], double(norm(moved[i] - cpu[i])));
    }
  std::size_t touching = 0;
  double worst = 0;
  for (std::uint32_t i = 0; i < n; ++i) {
    touching += norm(cpu[i]) > 0;
    const double allowed = 3 * spread[i] + 8 * kEps * norm(cpu[i]) + 1e-30;
    const double err = norm(out.f()[i] - cpu[i]);
    EXPECT_LE(err, allowed) << what << ": point " << i << " CPU " << cpu[i].x << ' ' << cpu[i].y
                            << ' ' << cpu[i].z;
    worst = std::max(worst, err / allowed);
  }
  std::printf("%s: %zu of %u points touching, worst error %.3g of its bound\n", what, touching, n,
              worst);
  EXPECT_GT(touching, n / 50) << what;
  return worst;
}

TEST_F(GpuObstacles, ContactForcesMatchTheCpuOnEveryShape) {
  for (const ShapeRow& row : shape_table())
    for (const bool world : {false, true}) {
      const ShapeKind shape = shape_kind(row.name);
      const bool moving = shape == shape_kind("cube") || shape == shape_kind("torus") ||
                          shape == shape_kind("plane");
      const std::string what =
          std::string(row.name) + (world ? ", world normal" : "") + (moving ? ", rotating" : "");
      expect_forces_match(tilted(shape, world, moving), what.c_str());
    }
}

// A 16 x 16 cloth, 0.6 m square, 5 cm above `obstacle` (TOML) at y = 0, falling.
Scene cloth_over(const std::string& obstacle, double top = 0.25) {
  const std::string text =
      "[simulation]\nstep = 2e-4\n[fields]\ngravity = [0.0, -9.81, 0.0]\nair_drag = 0.1\n"
      "[[flag]]\nname = \"cloth\"\norigin = [-0.3, " +
      std::to_string(top + 0.05) +
      ", -0.3]\nalong = [1.0, 0.0, 0.0]\nup = [0.0, 0.0, 1.0]\nwidth = 0.6\nheight = 0.6\n"
      "resolution = [16, 16]\nmass = 0.2\nstiffness = 300.0\nshear_stiffness = 100.0\n"
      "bending_stiffness = 1.0\ndamping = 0.02\nfixed = \"none\"\n" +
      obstacle;
  auto s = parse_scene(text, "cloth_over.toml", LinkKindRegistry::with_builtins(),
                       StageRegistry::with_builtins());
  if (!s) throw std::runtime_error(s.error().to_string());
  return std::move(s.value());
}

// 0.3 s of the fall (the cloth reaches the obstacle after 0.1 s): the GPU within 4 times the
// float-storage drift of the CPU. Returns the GPU's positions.
std::vector<Vec3> expect_run_matches(const Scene& scene, const char* what) {
  const std::uint64_t steps = 1500;
  const auto cpu = test::run_on(scene, "cpu", steps),
             rounded = test::run_on(scene, "cpu", steps, true),
             gpu = test::run_on(scene, "gpu", steps);
  const double drift = test::max_distance(cpu, rounded), off = test::max_distance(cpu, gpu);
  std::printf("%s, %llu steps: GPU - CPU %.3g m, float-storage drift %.3g m (ratio %.2f)\n", what,
              static_cast<unsigned long long>(steps), off, drift, off / drift);
  EXPECT_GT(drift, 0.0) << what;
  EXPECT_LE(off, 4 * drift + 1e-6) << what;
  return gpu;
}

TEST_F(GpuObstacles, ClothOnASphereStaysWithinTheFloatStorageDrift) {
  const Scene s = cloth_over(
      "[[obstacle]]\nname = \"ball\"\nshape = \"sphere\"\nscale = [0.25, 0.25, 0.25]\n"
      "stiffness = 2000.0\ndamping = 0.5\n");
  const auto x = expect_run_matches(s, "cloth on a sphere");
  // The cloth rests on the ball: its centre point is near the top, not through it.
  EXPECT_GT(test::max_abs(x), 0.2);
  double lowest_over_ball = 1;
  for (const Vec3& p : x)
    if (std::hypot(double(p.x), double(p.z)) < 0.05)
      lowest_over_ball = std::min(lowest_over_ball, double(p.y));
  EXPECT_GT(lowest_over_ball, 0.24);
}

TEST_F(GpuObstacles, ClothOnATiltedBoxStaysWithinTheFloatStorageDrift) {
  expect_run_matches(cloth_over("[[obstacle]]\nname = \"box\"\nshape = \"cube\"\n"
                                "rotation = [0.0, 30.0, 10.0]\nscale = [0.2, 0.2, 0.15]\n"
                                "stiffness = 2000.0\ndamping = 0.5\nnormal = \"world\"\n",
                                0.22),
                     "cloth on a tilted box");
}

TEST_F(GpuObstacles, ClothOnAPlaneWithFrictionStaysWithinTheFloatStorageDrift) {
  // A slope of 20 degrees with mu = 0.5: the cloth lands and grips.
  expect_run_matches(cloth_over("[[obstacle]]\nname = \"slope\"\nshape = \"plane\"\n"
                                "position = [0.0, 0.2, 0.0]\nrotation = [0.0, 0.0, 20.0]\n"
                                "stiffness = 2000.0\ndamping = 0.5\nfriction = 0.5\n",
                                0.32),
                     "cloth on a plane with friction");
}

TEST_F(GpuObstacles, ClothOnAMovingObstacleStaysWithinTheFloatStorageDrift) {
  // A capsule turning about y under the cloth and a ground rising and falling, both with
  // friction: the surfaces' velocities enter the damper and the friction.
  expect_run_matches(
      cloth_over(
          "[[obstacle]]\nname = \"roller\"\nshape = \"capsule\"\n"
          "rotation = [0.0, 0.0, 90.0]\nscale = [0.08, 0.2, 0.08]\nstiffness = 2000.0\n"
          "damping = 0.5\nfriction = 0.6\nmotion = { path = \"rotate\", axis = [0.0, 1.0, "
          "0.0], frequency = 0.5 }\n"
          "[[obstacle]]\nname = \"ground\"\nshape = \"plane\"\nposition = [0.0, -0.1, 0.0]\n"
          "stiffness = 2000.0\ndamping = 0.5\nfriction = 0.3\n"
          "motion = { path = \"oscillate\", amplitude = [0.0, 0.05, 0.0], frequency = 3.0 }\n",
          0.08),
      "cloth on a turning capsule and an oscillating ground");
}

// At rest on a horizontal plane a point sinks d = m g / k (the damper and friction vanish at
// rest). Damping ratio z / (2 sqrt(k m)) = 0.5 at omega = 100 rad/s: after 2 s the oscillation
// has decayed by e^-100. The GPU's equilibrium is float's: k d = m g to a few roundings of each
// side, and d = y0 - y to the rounding of y0, so |d - m g / k| <= 8 eps (d + y0).
TEST_F(GpuObstacles, APointRestsOnAPlaneAtItsPenetrationMgOverK) {
  const double y0 = 0.37, m = 0.01, k = 100, g = 9.81;
  const std::string text =
      "[simulation]\nstep = 1e-3\n[fields]\ngravity = [0.0, -9.81, 0.0]\n"
      "[[mass]]\nname = \"p\"\nposition = [0.1, 0.4, -0.2]\nmass = 0.01\n"
      "[[obstacle]]\nname = \"floor\"\nshape = \"plane\"\nposition = [0.0, 0.37, 0.0]\n"
      "stiffness = 100.0\ndamping = 1.0\nfriction = 0.5\n";
  auto scene = parse_scene(text, "rest.toml", LinkKindRegistry::with_builtins(),
                           StageRegistry::with_builtins());
  ASSERT_TRUE(scene) << scene.error().to_string();
  for (const std::string backend : {"cpu", "gpu"}) {
    SimulationSettings st = scene->settings;
    st.backend = backend;
    Simulator sim(scene->model, st);
    sim.run_steps(2000);
    const double depth = y0 - double(sim.state().x()[0].y), expected = m * g / k;
    const double tol = backend == "gpu" ? 8 * kEps * (expected + y0) : 1e-12;
    std::printf("%s: depth %.9g m, m g / k = %.9g m\n", backend.c_str(), depth, expected);
    EXPECT_NEAR(depth, expected, tol) << backend;
  }
}

TEST_F(GpuObstacles, OtherMethodsAreRefusedByName) {
  for (const char* method : {"facets", "conditional"}) {
    Scene s =
        cloth_over(std::string("[[obstacle]]\nname = \"ball\"\nshape = \"sphere\"\nmethod = \"") +
                   method + "\"\nscale = [0.25, 0.25, 0.25]\n");
    s.settings.backend = "gpu";
    try {
      Simulator sim(s.model, s.settings);
      ADD_FAILURE() << method << " accepted";
    } catch (const std::invalid_argument& e) {
      const std::string why = e.what();
      EXPECT_NE(why.find("stage 'obstacle:ball' has no GPU version"), std::string::npos) << why;
      EXPECT_NE(why.find("method = \"geometric\""), std::string::npos) << why;
    }
  }
}

}  // namespace
}  // namespace maille
