// Smooth surfaces over the physical mesh: the surface must pass through every particle,
// its normals must be those of the surface (finite differences), and a flat cloth must stay flat.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "example_run.hpp"
#include "maille/scene.hpp"
#include "maille/simulator.hpp"
#include "maille/smooth_surface.hpp"

namespace maille {
namespace {

Vec3 vertex(const SmoothMesh& m, std::size_t v) {
  return {m.vertices[6 * v], m.vertices[6 * v + 1], m.vertices[6 * v + 2]};
}
Vec3 normal(const SmoothMesh& m, std::size_t v) {
  return {m.vertices[6 * v + 3], m.vertices[6 * v + 4], m.vertices[6 * v + 5]};
}
Real extent(std::span<const Vec3> x) {
  Vec3 lo = x.front(), hi = lo;
  for (const Vec3& p : x)
    lo = {std::min(lo.x, p.x), std::min(lo.y, p.y), std::min(lo.z, p.z)},
    hi = {std::max(hi.x, p.x), std::max(hi.y, p.y), std::max(hi.z, p.z)};
  return norm(hi - lo);
}

// Floats carry 24 bits: a position of size L is exact to about 6e-8 L, and a few operations of
// the patch (16 weighted terms) make that about 1e-6 L at most.
constexpr Real kFloatTolerance = 1e-6;

TEST(SmoothSurface, GridClothPassesThroughEveryParticle) {
  Scene scene;
  const std::vector<Vec3> x = test::run_example("flag_in_wind", 2000, scene);
  const SmoothSurface smooth(scene.model);
  ASSERT_EQ(smooth.grids().size(), 1u);
  EXPECT_TRUE(smooth.other_triangles().empty());
  const SmoothSurface::Grid g = smooth.grids()[0];
  for (int lod : {1, 3, 8}) {
    SmoothMesh mesh;
    smooth.evaluate(x, lod, mesh);
    ASSERT_EQ(mesh.vertex_count(), smooth.vertex_count(lod));
    const std::uint32_t cols = std::uint32_t(lod) * (g.nx - 1) + 1;
    for (std::uint32_t j = 0; j < g.ny; ++j)
      for (std::uint32_t i = 0; i < g.nx; ++i) {
        const Vec3 s = vertex(mesh, j * std::uint32_t(lod) * cols + i * std::uint32_t(lod));
        EXPECT_LT(norm(s - x[g.first + j * g.nx + i]), kFloatTolerance * extent(x))
            << "lod " << lod << " particle (" << i << ", " << j << ")";
      }
  }
}

TEST(SmoothSurface, PnTrianglesPassThroughEveryCorner) {
  Scene scene;
  const std::vector<Vec3> x = test::run_example("drum_membrane", 1500, scene);
  const SmoothSurface smooth(scene.model);
  EXPECT_TRUE(smooth.grids().empty());
  const auto& tris = smooth.other_triangles();
  ASSERT_FALSE(tris.empty());
  const int lod = 4;
  SmoothMesh mesh;
  smooth.evaluate(x, lod, mesh);
  const std::uint32_t per = SmoothSurface::vertices_per_triangle(lod);
  // Corners of each triangle's lattice: (0, 0) -> a, (lod, 0) -> b, (0, lod) -> c.
  for (std::size_t t = 0; t < tris.size() / 3; ++t) {
    const std::size_t base = t * per;
    EXPECT_LT(norm(vertex(mesh, base) - x[tris[3 * t]]), kFloatTolerance * extent(x));
    EXPECT_LT(norm(vertex(mesh, base + std::size_t(lod)) - x[tris[3 * t + 1]]),
              kFloatTolerance * extent(x));
    EXPECT_LT(norm(vertex(mesh, base + per - 1) - x[tris[3 * t + 2]]), kFloatTolerance * extent(x));
  }
}

// The normal at a lattice vertex against the cross product of central differences of its
// neighbours. At lod 16 the differences span 1/8 of a physical edge: their error is second
// order, (h^2 / 6) |S'''| / |S'|, under 0.01 rad on these cloths, far above float rounding.
void expect_normals_match_differences(const SmoothMesh& mesh, std::size_t centre, std::size_t left,
                                      std::size_t right, std::size_t down, std::size_t up,
                                      int& checked) {
  const Vec3 tu = vertex(mesh, right) - vertex(mesh, left);
  const Vec3 tv = vertex(mesh, up) - vertex(mesh, down);
  const Vec3 fd = cross(tu, tv);
  if (!(norm(fd) > 0)) return;
  const Vec3 n = normal(mesh, centre);
  const Real angle = std::acos(std::clamp<Real>(dot(fd / norm(fd), n / norm(n)), -1, 1));
  EXPECT_LT(angle, 0.01) << "vertex " << centre;
  ++checked;
}

// Inside each cell the patch is a polynomial: its analytic tangents against central
// differences of the patch itself, delta = 1e-2 in parameter (truncation delta^2 / 6 times the
// third derivative, ~2e-5 relative; float rounding 6e-8 |S| / (delta |S_u|), ~1e-4 here): 2e-3
// holds both with room. The mesh's normals are those tangents' cross product.
TEST(SmoothSurface, GridNormalsAreTheSurfacesNormals) {
  Scene scene;
  const std::vector<Vec3> x = test::run_example("flag_in_wind", 2000, scene);
  const SmoothSurface smooth(scene.model);
  const int lod = 4;
  SmoothMesh mesh;
  smooth.evaluate(x, lod, mesh);
  const SmoothSurface::Grid g = smooth.grids_at(lod)[0];
  const float d = 1e-2f;
  int checked = 0;
  for (std::uint32_t j = 0; j + 1 < g.ny; j += 3)
    for (std::uint32_t i = 0; i + 1 < g.nx; i += 3)
      for (float u : {0.25f, 0.5f})
        for (float v : {0.25f, 0.75f}) {
          Vec3 s0, su, sv, a, b, t;
          smooth.grid_point(x, g, i, j, u, v, s0, su, sv);
          smooth.grid_point(x, g, i, j, u + d, v, a, t, t);
          smooth.grid_point(x, g, i, j, u - d, v, b, t, t);
          const Vec3 fu = (a - b) / Real(2 * d);
          smooth.grid_point(x, g, i, j, u, v + d, a, t, t);
          smooth.grid_point(x, g, i, j, u, v - d, b, t, t);
          const Vec3 fv = (a - b) / Real(2 * d);
          EXPECT_LT(norm(fu - su), 2e-3 * norm(su)) << "cell (" << i << ", " << j << ")";
          EXPECT_LT(norm(fv - sv), 2e-3 * norm(sv)) << "cell (" << i << ", " << j << ")";
          ++checked;
        }
  EXPECT_GT(checked, 100);
  // The mesh vertex at a cell's (1/4, 1/4) carries unit(su x sv) of that point.
  const std::size_t cols = std::size_t(lod) * (g.nx - 1) + 1;
  for (std::uint32_t j = 0; j + 1 < g.ny; j += 4)
    for (std::uint32_t i = 0; i + 1 < g.nx; i += 4) {
      Vec3 s0, su, sv;
      smooth.grid_point(x, g, i, j, 0.25f, 0.25f, s0, su, sv);
      const Vec3 n = cross(su, sv) / norm(cross(su, sv));
      const std::size_t at =
          (std::size_t(j) * std::size_t(lod) + 1) * cols + std::size_t(i) * std::size_t(lod) + 1;
      EXPECT_LT(norm(normal(mesh, at) - n), 1e-5);
      EXPECT_LT(norm(vertex(mesh, at) - s0), kFloatTolerance * extent(x));
    }
}

TEST(SmoothSurface, PnNormalsAreTheSurfacesNormals) {
  Scene scene;
  const std::vector<Vec3> x = test::run_example("drum_membrane", 1500, scene);
  const SmoothSurface smooth(scene.model);
  const int lod = 16;
  SmoothMesh mesh;
  smooth.evaluate(x, lod, mesh);
  const std::size_t per = SmoothSurface::vertices_per_triangle(lod);
  auto index = [&](int i, int j) { return std::size_t(j * (lod + 1) - j * (j - 1) / 2 + i); };
  int checked = 0;
  for (std::size_t t = 0; t < smooth.other_triangles().size() / 3; t += 7) {
    const std::size_t base = t * per;
    // An interior lattice vertex (i, j) = (5, 5): b-direction and c-direction differences.
    expect_normals_match_differences(mesh, base + index(5, 5), base + index(4, 5),
                                     base + index(6, 5), base + index(5, 4), base + index(5, 6),
                                     checked);
  }
  EXPECT_GT(checked, 20);
}

TEST(SmoothSurface, FlatClothStaysFlatAndFacesTheModelsWay) {
  Scene scene;
  const std::vector<Vec3> x =
      test::run_example("flag_in_wind", 0, scene);  // the initial, planar flag
  const SmoothSurface smooth(scene.model);
  SmoothMesh mesh;
  smooth.evaluate(x, 4, mesh);
  const auto& t = scene.model.surface.triangles.front();
  const Vec3 face = cross(x[t[1]] - x[t[0]], x[t[2]] - x[t[0]]);
  const Vec3 n = face / norm(face);
  for (std::size_t v = 0; v < mesh.vertex_count(); ++v) {
    EXPECT_NEAR(dot(vertex(mesh, v) - x[t[0]], n), 0, kFloatTolerance * extent(x));
    EXPECT_NEAR(dot(normal(mesh, v), n), 1, 1e-6);
  }
  // Triangles wind like the model's: their normals agree with the vertex normals.
  for (std::size_t k = 0; k + 2 < mesh.triangles.size(); k += 3) {
    const Vec3 a = vertex(mesh, mesh.triangles[k]), b = vertex(mesh, mesh.triangles[k + 1]),
               c = vertex(mesh, mesh.triangles[k + 2]);
    EXPECT_GT(dot(cross(b - a, c - a), n), 0);
  }
}

TEST(SmoothSurface, RefusesBadInput) {
  Scene scene;
  const std::vector<Vec3> x = test::run_example("flag_in_wind", 0, scene);
  const SmoothSurface smooth(scene.model);
  SmoothMesh mesh;
  EXPECT_THROW(smooth.evaluate(x, 0, mesh), std::invalid_argument);
  EXPECT_THROW(smooth.evaluate(x, kMaxSmoothLod + 1, mesh), std::invalid_argument);
  EXPECT_THROW(smooth.evaluate(std::span<const Vec3>(x).first(3), 2, mesh), std::invalid_argument);
}

}  // namespace
}  // namespace maille
