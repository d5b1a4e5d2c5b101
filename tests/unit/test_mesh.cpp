// Tessellated shapes and TriMesh's measures: every shape is closed (the plane excepted),
// outward, welded, on its canonical surface, and its volume and area converge to the analytic
// values at the rate of inscribed polygons. (Suites are named mesh_*: `ctest -R mesh` is
// case-sensitive.)
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "maille/mesh.hpp"
#include "maille/shapes.hpp"

namespace maille {
namespace {

constexpr double kPi = std::numbers::pi;

// One shape with its exact measures and the number of profile segments a full turn would have
// (0 where the profile is straight), mirroring the sweep's choice in the shape table's meshes
// (shape_table.cpp): segments about 2 pi / n long.
struct Case {
  ShapeKind kind;
  std::optional<Real> parameter;  // the cone's top, the torus's tube; none: the default
  double volume, area;
  bool swept = true;  // a solid of revolution: the around-the-axis term applies
  int (*profile_turn)(int n, double parameter) = nullptr;
  std::string label;
};

int ceil_div(double x) {
  return static_cast<int>(std::ceil(x - 1e-9));
}

std::vector<Case> cases() {
  std::vector<Case> c;
  c.push_back({shape_kind("sphere"), std::nullopt, 4 * kPi / 3, 4 * kPi, true,
               [](int n, double) { return 2 * ceil_div(n / 2.0); }, "sphere"});
  c.push_back({shape_kind("cube"), std::nullopt, 8, 24, false, nullptr, "cube"});
  c.push_back({shape_kind("cylinder"), std::nullopt, 2 * kPi, 6 * kPi, true, nullptr, "cylinder"});
  for (const double top : {0.0, 0.25, 0.5, 1.0}) {
    const double slant = std::hypot(2.0, 1 - top);
    c.push_back({shape_kind("cone"), Real(top), 2 * kPi / 3 * (1 + top + top * top),
                 kPi * (1 + top) * slant + kPi + kPi * top * top, true, nullptr,
                 "cone top " + std::to_string(top)});
  }
  for (const double tube : {0.1, 0.25, 0.3, 1.0})
    c.push_back({shape_kind("torus"), Real(tube), 2 * kPi * kPi * tube * tube, 4 * kPi * kPi * tube,
                 true, [](int n, double t) { return std::max(3, ceil_div(n * t)); },
                 "torus tube " + std::to_string(tube)});
  c.push_back({shape_kind("capsule"), std::nullopt, 2 * kPi + 4 * kPi / 3, 8 * kPi, true,
               [](int n, double) { return 4 * ceil_div(n / 4.0); }, "capsule"});
  return c;
}

// The error bound, per curved direction with k segments per turn, theta = 2 pi / k: 3 theta^2 / 8.
// Around the axis the sweep is exact up to the inscribed n-gon: every cross-section keeps
// sin(theta)/theta of its area, a deficit below theta^2 / 6. Along a curved profile each chord
// lies at least cos(theta/2) of the radius from its centre of curvature, so the mesh holds the
// shape shrunk by that factor: volume deficit 1 - cos^3(theta/2) <= 3 theta^2 / 8, area deficit
// 1 - cos^2(theta/2) <= theta^2 / 4. (The torus, not convex, has Pappus instead: its tube's
// inscribed m-gon keeps its centroid at radius 1, a deficit below theta^2 / 6.) The relative
// errors of volume and area are held to the sum over the curved directions; flat shapes are
// exact.
double bound(const Case& c, int n) {
  auto term = [](int k) { return 3 * std::pow(2 * kPi / k, 2) / 8; };
  double b = c.swept ? term(n) : 0;
  if (c.profile_turn) b += term(c.profile_turn(n, double(c.parameter.value_or(0))));
  return std::max(b, 1e-12);
}

double relative(double value, double exact) {
  return std::abs(value - exact) / exact;
}

TEST(mesh_shapes, ClosedOutwardAndConverging) {
  for (const Case& c : cases()) {
    double previous_error = 0;
    for (const int n : {8, 16, 32, 64}) {
      SCOPED_TRACE(c.label + ", resolution " + std::to_string(n));
      const TriMesh m = tessellate(c.kind, n, c.parameter);
      EXPECT_TRUE(m.closed());
      const double v = double(m.volume()), a = double(m.area());
      EXPECT_GT(v, 0);
      EXPECT_LE(relative(v, c.volume), bound(c, n));
      EXPECT_LE(relative(a, c.area), bound(c, n));
      // Second order: doubling the segments in every curved direction divides the error by
      // about 4 (by 3 at least). The torus's tube segments, ceil(n tube), do not always double.
      const double error = relative(v, c.volume);
      const bool doubled =
          !c.profile_turn || c.profile_turn(n, double(c.parameter.value_or(0))) ==
                                 2 * c.profile_turn(n / 2, double(c.parameter.value_or(0)));
      if (c.swept && previous_error > 0 && doubled) {
        EXPECT_LT(error, previous_error / 3);
      }
      previous_error = error;
    }
  }
}

TEST(mesh_shapes, VerticesOnTheCanonicalSurface) {
  std::vector<Case> all = cases();
  all.push_back({shape_kind("plane"), std::nullopt, 0, 4, false, nullptr, "plane"});
  for (const Case& c : all)
    for (const int n : {3, 5, 12, 33}) {
      SCOPED_TRACE(c.label + ", resolution " + std::to_string(n));
      const TriMesh m = tessellate(c.kind, n, c.parameter);
      double worst = 0;
      for (const Vec3& p : m.vertices)
        worst = std::max(
            worst,
            std::abs(double(shapes::canonical(c.kind, p, shape_parameter(c.kind, c.parameter))
                                .signed_distance)));
      EXPECT_LT(worst, 1e-12);
    }
}

// Welded and clean: no vertex repeated (shared edges are shared indices), no unused vertex,
// no triangle of zero area.
TEST(mesh_shapes, WeldedWithoutDegenerateTriangles) {
  std::vector<Case> all = cases();
  all.push_back({shape_kind("plane"), std::nullopt, 0, 4, false, nullptr, "plane"});
  for (const Case& c : all) {
    SCOPED_TRACE(c.label);
    const TriMesh m = tessellate(c.kind, 16, c.parameter);
    std::vector<Vec3> sorted = m.vertices;
    auto less = [](const Vec3& a, const Vec3& b) {
      return a.x != b.x ? a.x < b.x : a.y != b.y ? a.y < b.y : a.z < b.z;
    };
    std::sort(sorted.begin(), sorted.end(), less);
    EXPECT_EQ(std::adjacent_find(sorted.begin(), sorted.end()), sorted.end());
    std::vector<bool> used(m.vertices.size());
    for (const auto& t : m.triangles) {
      for (const auto i : t) used[i] = true;
      const Vec3 a = m.vertices[t[0]];
      EXPECT_GT(norm(cross(m.vertices[t[1]] - a, m.vertices[t[2]] - a)), 1e-6);
    }
    EXPECT_EQ(std::count(used.begin(), used.end(), false), 0);
  }
}

TEST(mesh_shapes, PlaneIsAnOpenSquareFacingUp) {
  const TriMesh m = tessellate(shape_kind("plane"), 5);
  EXPECT_EQ(m.triangles.size(), 2u * 5 * 5);
  EXPECT_EQ(m.vertices.size(), 6u * 6);
  EXPECT_FALSE(m.closed());
  EXPECT_NEAR(double(m.area()), 4, 1e-12);
  for (const auto& t : m.triangles) {
    const Vec3 n = cross(m.vertices[t[1]] - m.vertices[t[0]], m.vertices[t[2]] - m.vertices[t[0]]);
    EXPECT_GT(n.y, 0);
    EXPECT_EQ(n.x, 0);
    EXPECT_EQ(n.z, 0);
  }
  EXPECT_EQ(tessellate(shape_kind("plane"), 1).triangles.size(), 2u);
}

TEST(mesh_shapes, PointedConeHasAnApex) {
  const TriMesh m = tessellate(shape_kind("cone"), 12, 0);
  EXPECT_TRUE(m.closed());
  EXPECT_EQ(std::count(m.vertices.begin(), m.vertices.end(), Vec3{0, 1, 0}), 1);
}

TEST(mesh_shapes, IcosphereFacesAndRadius) {
  for (int level = 0; level <= 4; ++level) {
    SCOPED_TRACE(level);
    const TriMesh m = icosphere(level);
    EXPECT_EQ(m.triangles.size(), std::size_t(20) << (2 * level));
    EXPECT_EQ(m.vertices.size(), 10 * (std::size_t(1) << (2 * level)) + 2);  // Euler
    EXPECT_TRUE(m.closed());
    EXPECT_GT(m.volume(), 0);
    for (const Vec3& p : m.vertices) EXPECT_NEAR(double(norm(p)), 1, 1e-15);
  }
  // Level 4's triangles are about 2 pi / 80 across: the volume is within a few 1e-3.
  EXPECT_NEAR(double(icosphere(4).volume()), 4 * kPi / 3, 4 * kPi / 3 * 0.01);
}

TEST(mesh_shapes, ArgumentsOutOfRangeAreRefused) {
  EXPECT_THROW(tessellate(shape_kind("sphere"), 2), std::invalid_argument);
  EXPECT_THROW(tessellate(shape_kind("sphere"), 1025), std::invalid_argument);
  EXPECT_THROW(tessellate(shape_kind("plane"), 0), std::invalid_argument);
  EXPECT_THROW(tessellate(shape_kind("cone"), 8, Real(1.5)), std::invalid_argument);
  EXPECT_THROW(tessellate(shape_kind("cone"), 8, Real(NAN)), std::invalid_argument);
  EXPECT_THROW(tessellate(shape_kind("torus"), 8, 0), std::invalid_argument);
  EXPECT_THROW(icosphere(-1), std::invalid_argument);
  EXPECT_THROW(icosphere(9), std::invalid_argument);
}

// closed() looks at edges only: orientation and manifoldness, not geometry.
TEST(mesh_shapes, ClosedNeedsEveryEdgeTwiceInOppositeDirections) {
  TriMesh tetra;
  tetra.vertices = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  tetra.triangles = {{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}};
  EXPECT_TRUE(tetra.closed());
  EXPECT_NEAR(double(tetra.volume()), 1.0 / 6, 1e-15);
  EXPECT_NEAR(double(tetra.area()), 1.5 + std::sqrt(3.0) / 2, 1e-15);

  TriMesh flipped = tetra;  // one face turned over: its edges run the same way as neighbours'
  std::swap(flipped.triangles[3][1], flipped.triangles[3][2]);
  EXPECT_FALSE(flipped.closed());
  TriMesh open = tetra;
  open.triangles.pop_back();
  EXPECT_FALSE(open.closed());
  TriMesh doubled = tetra;  // a face twice: its edges are used three times
  doubled.triangles.push_back(tetra.triangles[0]);
  EXPECT_FALSE(doubled.closed());
  TriMesh inside_out = tetra;
  for (auto& t : inside_out.triangles) std::swap(t[1], t[2]);
  EXPECT_TRUE(inside_out.closed());
  EXPECT_LT(inside_out.volume(), 0);
  EXPECT_FALSE(TriMesh{}.closed());
}

}  // namespace
}  // namespace maille
