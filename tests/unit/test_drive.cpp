// Scripted fixed points: each path against its formula, and a driven point in a simulation sits
// exactly on its path at every published frame.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "maille/scene.hpp"

namespace maille {
namespace {

TEST(Drive, SinePositionAndVelocity) {
  DrivePath p;
  p.kind = DrivePath::Kind::sine;
  p.origin = {1, 2, 3};
  p.amplitude = {0, 0.5, 0};
  p.frequency = 2;
  p.phase = 0.3;
  const double t = 0.37, w = 2 * std::numbers::pi * 2;
  EXPECT_NEAR(p.position(0).y, 2, 1e-15);  // starts at its scene position
  EXPECT_NEAR(p.position(t).y, 2 + 0.5 * (std::sin(w * t + 0.3) - std::sin(0.3)), 1e-14);
  EXPECT_NEAR(p.velocity(t).y, 0.5 * w * std::cos(w * t + 0.3), 1e-12);
  EXPECT_NEAR(p.max_speed(), 0.5 * w, 1e-12);
}

// Rotation about a line, rigid and twisted: starts at its scene position, keeps its distance to
// the axis and its axial coordinate, turns at 2 pi f a rad/s, and its velocity is the derivative
// of its position.
TEST(Drive, RotateAndTwist) {
  for (Real length : {Real(0), Real(2)}) {
    DrivePath p;
    p.kind = DrivePath::Kind::rotate;
    p.center = {0, 1, 0};
    p.axis = {2, 0, 0};  // not unit: normalised
    p.frequency = 0.5;
    p.length = length;
    p.origin = {1, 1.3, 0.4};  // axial coordinate 1, distance 0.5 from the axis
    EXPECT_LT(norm(p.position(0) - p.origin), 1e-15);
    const Real a = length > 0 ? Real(0.5) : Real(1);  // 1 / 2 of the twist length
    for (double t : {0.2, 0.7, 1.9}) {
      const Vec3 x = p.position(t);
      EXPECT_NEAR(x.x, 1, 1e-14);
      EXPECT_NEAR(std::hypot(x.y - 1, x.z), 0.5, 1e-14);
      const double angle = std::atan2(x.z, x.y - 1) - std::atan2(0.4, 0.3);
      EXPECT_NEAR(std::remainder(angle - 2 * std::numbers::pi * 0.5 * t * a, 2 * std::numbers::pi),
                  0, 1e-12);
      const double h = 1e-6;
      const Vec3 fd = (p.position(t + h) - p.position(t - h)) / Real(2 * h);
      EXPECT_LT(norm(fd - p.velocity(t)), 1e-8);
    }
    EXPECT_NEAR(p.max_speed(), 2 * std::numbers::pi * 0.5 * a * 0.5, 1e-12);
  }
}

TEST(Drive, CircleKeepsItsRadiusAndStartsAtOrigin) {
  DrivePath p;
  p.kind = DrivePath::Kind::circle;
  p.origin = {0, 1, 0};
  p.radius = 0.2;
  p.axis = {0, 0, 1};
  p.frequency = 1;
  EXPECT_LT(norm(p.position(0) - p.origin), 1e-15);
  // The centre is the point of the circle's plane at distance r from every position.
  const Vec3 c = p.position(0.5) * Real(0.5) + p.position(0) * Real(0.5);
  for (double t : {0.1, 0.33, 0.71}) EXPECT_NEAR(norm(p.position(t) - c), 0.2, 1e-12);
  // Velocity is the derivative of position (central difference, h = 1e-6: error ~1e-12).
  const double h = 1e-6, t = 0.21;
  const Vec3 fd = (p.position(t + h) - p.position(t - h)) / Real(2 * h);
  EXPECT_LT(norm(fd - p.velocity(t)), 1e-7);
}

TEST(Drive, KeyframesInterpolateAndHold) {
  DrivePath p;
  p.kind = DrivePath::Kind::keyframes;
  p.keys = {{0, {0, 0, 0}}, {1, {1, 0, 0}}, {3, {1, 2, 0}}};
  EXPECT_NEAR(p.position(0.25).x, 0.25, 1e-15);
  EXPECT_NEAR(p.position(2).y, 1, 1e-15);
  EXPECT_NEAR(p.position(9).y, 2, 1e-15);
  EXPECT_NEAR(p.velocity(2).y, 1, 1e-15);
  EXPECT_EQ(p.velocity(9), Vec3{});
}

TEST(Drive, DrivenPointsFollowTheirPathInASimulation) {
  auto scene = parse_scene(R"(
[simulation]
step = 1e-3
output_every = 7
[[fixed]]
name = "hand"
position = [0, 1, 0]
drive = { path = "sine", amplitude = [0.3, 0, 0], frequency = 1.5 }
[[mass]]
name = "bob"
position = [0, 0, 0]
[[link]]
kind = "spring_damper"
a = "hand"
b = "bob"
stiffness = 200.0
damping = 0.5
)",
                           "inline.toml", LinkKindRegistry::with_builtins());
  ASSERT_TRUE(scene.ok()) << scene.error().to_string();
  const std::uint32_t hand = scene->model.group("hand")->first;
  const DrivePath path = scene->model.drives.at(0).path;
  EXPECT_EQ(scene->model.points.kind[hand], PointKind::driven);
  Simulator sim(std::move(scene->model), scene->settings);
  int frames = 0;
  sim.on_publish([&](const Snapshot& s) {
    EXPECT_LT(norm(s.positions[hand] - path.position(s.time)), 1e-12) << "t = " << s.time;
    ++frames;
  });
  ASSERT_TRUE(sim.run_steps(700));
  EXPECT_EQ(frames, 100);
  // The bob is dragged along: it moved in x.
  EXPECT_GT(std::abs(sim.state().x()[1 - hand].x), 0.01);
}

}  // namespace
}  // namespace maille
