// Canonical distance functions against analytic penetration vectors: inside, outside, on the
// surface, at the centre and on ties (the documented rules); the gradient of the signed distance
// is the normal (central differences, 1e-6 step: error ~1e-9); affine maps round-trip.
#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <random>

#include "maille/shapes.hpp"

namespace maille::shapes {
namespace {

// Each shape's distance function, through the table's number (canonical_distance).
Distance sphere(const Vec3& p) {
  return canonical(shape_kind("sphere"), p);
}
Distance cube(const Vec3& p) {
  return canonical(shape_kind("cube"), p);
}
Distance cylinder(const Vec3& p) {
  return canonical(shape_kind("cylinder"), p);
}
Distance cone(const Vec3& p, Real top) {
  return canonical(shape_kind("cone"), p, top);
}
Distance torus(const Vec3& p, Real tube) {
  return canonical(shape_kind("torus"), p, tube);
}
Distance capsule(const Vec3& p) {
  return canonical(shape_kind("capsule"), p);
}
Distance half_space(const Vec3& p) {
  return canonical(shape_kind("plane"), p);
}

void expect_vec(const Vec3& a, const Vec3& b, double tol = 1e-12) {
  EXPECT_NEAR(a.x, b.x, tol);
  EXPECT_NEAR(a.y, b.y, tol);
  EXPECT_NEAR(a.z, b.z, tol);
}

TEST(Shapes, SphereAnalytic) {
  const Distance in = sphere({0.3, 0.4, 0});
  EXPECT_NEAR(in.signed_distance, -0.5, 1e-15);
  expect_vec(in.penetration(), {0.3, 0.4, 0});  // to the surface at (0.6, 0.8, 0)
  const Distance out = sphere({0, 0, 3});
  EXPECT_NEAR(out.signed_distance, 2, 1e-15);
  expect_vec(out.normal, {0, 0, 1});
  expect_vec(out.penetration(), {0, 0, 0});
  EXPECT_NEAR(sphere({0, -1, 0}).signed_distance, 0, 1e-15);
  expect_vec(sphere({0, 0, 0}).normal, {0, 1, 0});  // centre: +y
  EXPECT_NEAR(sphere({0, 0, 0}).signed_distance, -1, 1e-15);
}

TEST(Shapes, CubeAnalyticAndTies) {
  const Distance in = cube({0.2, -0.7, 0.1});
  EXPECT_NEAR(in.signed_distance, -0.3, 1e-15);
  expect_vec(in.normal, {0, -1, 0});
  const Distance corner = cube({2, 3, -1.5});  // outside near a corner: Euclidean
  EXPECT_NEAR(corner.signed_distance, std::sqrt(1.0 + 4 + 0.25), 1e-14);
  const Distance tie = cube({0.5, 0.5, 0.5});  // equidistant to three faces: +y first
  expect_vec(tie.normal, {0, 1, 0});
  expect_vec(cube({0.5, 0.2, 0.5}).normal, {1, 0, 0});  // x before z
  expect_vec(cube({0, 0, 0}).normal, {0, 1, 0});
  EXPECT_NEAR(cube({1, 0.3, 0}).signed_distance, 0, 1e-15);
}

TEST(Shapes, CylinderConeCapsuleTorusHalfSpace) {
  // Cylinder: inside nearer the side, nearer a cap; outside beyond the rim (diagonal).
  EXPECT_NEAR(cylinder({0.9, 0, 0}).signed_distance, -0.1, 1e-15);
  expect_vec(cylinder({0.9, 0, 0}).normal, {1, 0, 0});
  EXPECT_NEAR(cylinder({0, 0.95, 0.1}).signed_distance, -0.05, 1e-15);
  expect_vec(cylinder({0, 0.95, 0.1}).normal, {0, 1, 0});
  EXPECT_NEAR(cylinder({0, 2, 2}).signed_distance, std::sqrt(2.0), 1e-14);
  expect_vec(cylinder({0, 0, 0}).normal, {0, 1, 0});  // centre: top cap first
  // Cone frustum (top radius 0.5): the side's outward normal is (2, 0.5) / |(2, 0.5)| in (r, y).
  const Real top = 0.5;
  const Distance side = cone({2, 0, 0}, top);
  const double len = std::sqrt(4 + 0.25);
  expect_vec(side.normal, {2 / len, 0.5 / len, 0}, 1e-12);
  // The distance from (2, 0) to the side line through (1, -1) and (0.5, 1).
  EXPECT_NEAR(side.signed_distance, ((2 - 1) * 2 + (0 + 1) * 0.5) / len, 1e-12);
  EXPECT_LT(cone({0.7, 0.1, 0}, top).signed_distance, 0);
  EXPECT_GT(cone({0.76, 0.1, 0}, top).signed_distance, 0);    // radius at y = 0.1 is 0.725
  EXPECT_NEAR(cone({0, 1, 0}, 0).signed_distance, 0, 1e-15);  // the apex of a pointed cone
  // Capsule: side and end.
  EXPECT_NEAR(capsule({0.5, 0.3, 0}).signed_distance, -0.5, 1e-15);
  EXPECT_NEAR(capsule({0, 2.5, 0}).signed_distance, 0.5, 1e-15);
  expect_vec(capsule({0, 0.2, 0}).normal, {1, 0, 0});  // on the axis: +x
  // Torus (tube 0.3): the tube's centre circle, inside, outside, the axis.
  EXPECT_NEAR(torus({1, 0, 0}, 0.3).signed_distance, -0.3, 1e-15);
  expect_vec(torus({1, 0, 0}, 0.3).normal, {0, 1, 0});
  EXPECT_NEAR(torus({0, 0, 1.2}, 0.3).signed_distance, -0.1, 1e-15);
  expect_vec(torus({0, 0, 1.2}, 0.3).normal, {0, 0, 1});
  EXPECT_NEAR(torus({0, 0, 0}, 0.3).signed_distance, 0.7, 1e-15);
  EXPECT_NEAR(half_space({3, -0.2, 4}).signed_distance, -0.2, 1e-15);
  expect_vec(half_space({3, -0.2, 4}).penetration(), {0, 0.2, 0});
}

// Away from ties, the normal is the gradient of the signed distance.
TEST(Shapes, NormalIsTheGradient) {
  const std::vector<std::pair<const char*, std::function<Distance(const Vec3&)>>> all = {
      {"sphere", sphere},
      {"cube", cube},
      {"cylinder", cylinder},
      {"cone", [](const Vec3& p) { return cone(p, 0.4); }},
      {"torus", [](const Vec3& p) { return torus(p, 0.35); }},
      {"capsule", capsule},
      {"half_space", half_space}};
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(-2.5, 2.5);
  const double h = 1e-6;
  for (const auto& [name, f] : all) {
    int checked = 0;
    for (int i = 0; i < 4000 && checked < 400; ++i) {
      const Vec3 p{Real(u(rng)), Real(u(rng)), Real(u(rng))};
      const Distance d = f(p);
      Vec3 g;
      for (int k = 0; k < 3; ++k) {
        Vec3 e{};
        (k == 0 ? e.x : k == 1 ? e.y : e.z) = Real(h);
        (k == 0   ? g.x
         : k == 1 ? g.y
                  : g.z) = (f(p + e).signed_distance - f(p - e).signed_distance) / Real(2 * h);
      }
      if (std::abs(norm(g) - 1) > 1e-3) continue;  // a tie (a ridge of the distance): skip
      ++checked;
      EXPECT_LT(norm(g - d.normal), 1e-5) << name << " at " << p.x << "," << p.y << "," << p.z;
      EXPECT_NEAR(norm(d.normal), 1, 1e-12) << name;
    }
    EXPECT_GE(checked, 100) << name;
  }
}

TEST(Shapes, AffineRoundTripsPointsAndVectors) {
  const Affine a = Affine::from({1, 2, 3}, {30, -45, 110}, {0.5, 2, 1.5});
  // M_d M_i = I
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) {
      double s = 0;
      for (int k = 0; k < 3; ++k) s += a.direct.m[i][k] * a.inverse.m[k][j];
      EXPECT_NEAR(s, i == j ? 1 : 0, 1e-14);
    }
  const Vec3 p{0.3, -0.7, 1.1};
  expect_vec(a.to_canonical(a.to_world(p)), p, 1e-13);
  expect_vec(a.vector_to_canonical(a.vector_to_world(p)), p, 1e-13);
  // Rotation about z by 90 degrees takes x to y.
  const Affine r = Affine::from({0, 0, 0}, {0, 0, 90}, {1, 1, 1});
  expect_vec(r.to_world({1, 0, 0}), {0, 1, 0}, 1e-15);
  // The world normal stays perpendicular to world tangents under non-uniform scale.
  const Vec3 tangent_c{1, 0, 0}, normal_c{0, 1, 0};
  EXPECT_NEAR(dot(a.vector_to_world(tangent_c), a.normal_to_world(normal_c)), 0, 1e-14);
}

}  // namespace
}  // namespace maille::shapes
