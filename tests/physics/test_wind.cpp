// The wind stage against its law (WindField, fields.hpp): one face against the formula, the
// faces of a grid (the flag's, run row by row with each point gathering its six faces) against
// the formula and against the general path (coloured faces scattered to their corners), the
// total force against the sum over faces, and one thread against two, bit for bit.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "maille/simulator.hpp"
#include "test_support.hpp"

namespace maille {
namespace {

void set_wind(Model& m, bool gusty) {
  m.fields.gravity = {0, 0, 0};
  m.fields.wind.velocity = {7, 0.5, 1.5};
  m.fields.wind.turbulence = gusty ? Real(0.35) : Real(0);
  m.fields.wind.gust_frequency = Real(0.8);
  m.fields.wind.gust_wavelength = Real(1.5);
}

// nx x ny points, crumpled and moving, with the flag builder's faces; declared as a grid group
// or not (then every face takes the general path).
Model cloth(std::uint32_t nx, std::uint32_t ny, bool gusty, bool as_grid) {
  Model m;
  set_wind(m, gusty);
  for (std::uint32_t j = 0; j < ny; ++j)
    for (std::uint32_t i = 0; i < nx; ++i) {
      const double x = i, y = j;
      m.points.add(PointKind::free, Real(0.01),
                   {Real(0.05 * x), Real(0.05 * y), Real(0.02 * std::sin(0.7 * x + 1.3 * y))},
                   {Real(0.3 * std::cos(0.5 * x)), Real(0.2 * std::sin(0.9 * y)),
                    Real(2 * std::sin(0.3 * x + 0.2 * y))});
    }
  for (std::uint32_t j = 0; j + 1 < ny; ++j)
    for (std::uint32_t i = 0; i + 1 < nx; ++i) {
      const std::uint32_t p = j * nx + i;
      m.surface.triangles.push_back({p, p + 1, p + nx + 1});
      m.surface.triangles.push_back({p, p + nx + 1, p + nx});
    }
  if (as_grid) {
    Group g;
    g.name = "cloth";
    g.builder = "flag";
    g.count = nx * ny;
    g.grid_nx = nx;
    g.grid_ny = ny;
    m.groups.push_back(g);
  }
  return m;
}

// The law written out per face (fields.hpp): F = 1/2 rho C_d A |v_rel.n| (v_rel.n) n, a third to
// each corner, with w from WindField::at at the centre, at time 0.
std::vector<Vec3> law(const Model& m) {
  std::vector<Vec3> f(m.points.size());
  const WindField& w = m.fields.wind;
  for (const auto& [a, b, c] : m.surface.triangles) {
    const Vec3 xa = m.points.initial_position[a], xb = m.points.initial_position[b],
               xc = m.points.initial_position[c];
    const Vec3 n2 = cross(xb - xa, xc - xa);
    const Real area = norm(n2) / 2;
    if (area == 0) continue;
    const Vec3 n = n2 / norm(n2);
    const Vec3 centre = (xa + xb + xc) / Real(3);
    const Vec3 vs =
        m.points.initial_velocity[a] + m.points.initial_velocity[b] + m.points.initial_velocity[c];
    const Real vn = dot(w.at(centre, 0) - vs / Real(3), n);
    const Vec3 corner =
        n * (Real(0.5) * w.density * w.drag_coefficient * area * std::abs(vn) * vn / Real(3));
    f[a] += corner;
    f[b] += corner;
    f[c] += corner;
  }
  return f;
}

// The stage's forces at the initial state: the first step of explicit Euler evaluates them at
// time 0 and leaves them in the state.
std::vector<Vec3> stage(Model m, int threads, std::uint64_t* faces = nullptr) {
  SimulationSettings s = test::settings(1e-5);
  s.integrator = "explicit_euler";
  s.threads = threads;
  Simulator sim(std::move(m), s);
  EXPECT_TRUE(sim.step());
  EXPECT_EQ(sim.threads(), threads);
  if (faces)
    for (const auto& c : sim.profile().counters())
      if (c.name == "wind_faces") *faces = c.last;
  return {sim.state().f().begin(), sim.state().f().end()};
}

// Largest |got - want| over the points, relative to the largest |want|.
double relative_error(const std::vector<Vec3>& got, const std::vector<Vec3>& want) {
  double worst = 0, scale = 0;
  for (std::size_t p = 0; p < want.size(); ++p) {
    worst = std::max<double>(worst, norm(got[p] - want[p]));
    scale = std::max<double>(scale, norm(want[p]));
  }
  return worst / scale;
}

// Tolerances. Steady wind: the stage computes the same law with its products rearranged
// (|d| d / |a2|^2 a2 instead of a unit normal and an area), rounding only: 1e-12. Gusts: the
// stage's face coordinates along and across the wind are its corners' mean rather than the
// centre's, which can move each sine's argument by one float rounding (3e-8 turn, 2e-7 on the
// sine), so the air velocity by ~1e-6 m/s out of 7: 1e-5 leaves a wide margin.
constexpr double steady_tolerance = 1e-12, gusty_tolerance = 1e-5;
// The grid path evaluates the law in float (edges and velocity sums rounded once from double,
// then about ten float operations, each within 2^-24 = 6e-8): 1e-6 of the largest force, where
// 1.5e-7 is measured.
constexpr double grid_steady_tolerance = 1e-6;

TEST(WindStage, SingleFaceMatchesTheLaw) {
  for (const bool gusty : {false, true}) {
    Model m;
    set_wind(m, gusty);
    m.points.add(PointKind::free, 1, {0.1, 2.0, 0.3}, {0.5, -0.2, 1.0});
    m.points.add(PointKind::free, 1, {0.4, 2.1, -0.2}, {0.1, 0.3, -0.4});
    m.points.add(PointKind::free, 1, {0.2, 2.5, 0.1}, {-0.3, 0.2, 0.6});
    m.surface.triangles.push_back({0, 1, 2});
    const std::vector<Vec3> want = law(m);
    std::uint64_t faces = 0;
    const std::vector<Vec3> got = stage(m, 1, &faces);
    EXPECT_LT(relative_error(got, want), gusty ? gusty_tolerance : steady_tolerance) << gusty;
    EXPECT_GT(norm(want[0]), 1e-3);  // the face is pushed, not edge-on
    EXPECT_EQ(faces, 1u);
    // Pressure only: along the normal, the same on the three corners.
    EXPECT_EQ(got[0], got[1]);
    EXPECT_EQ(got[0], got[2]);
  }
}

// 150 x 6 points: three tiles of a row (64, 64, 22 points) and rows split among threads.
TEST(WindStage, GridFacesMatchTheLawAndTheGeneralPath) {
  for (const bool gusty : {false, true}) {
    const Model grid = cloth(150, 6, gusty, true), loose = cloth(150, 6, gusty, false);
    {
      Model prepared = grid;
      prepared.prepare();
      ASSERT_EQ(prepared.surface.grids.size(), 1u);
      EXPECT_TRUE(prepared.surface.loose.empty());
      Model general = loose;
      general.prepare();
      EXPECT_TRUE(general.surface.grids.empty());
      EXPECT_EQ(general.surface.loose.size(), general.surface.triangles.size());
    }
    const std::vector<Vec3> want = law(grid);
    std::uint64_t grid_faces = 0, loose_faces = 0;
    const std::vector<Vec3> by_grid = stage(grid, 1, &grid_faces);
    const std::vector<Vec3> by_faces = stage(loose, 1, &loose_faces);
    const double tolerance = gusty ? gusty_tolerance : grid_steady_tolerance;
    EXPECT_LT(relative_error(by_grid, want), tolerance) << gusty;
    EXPECT_LT(relative_error(by_faces, want), gusty ? gusty_tolerance : steady_tolerance) << gusty;
    EXPECT_LT(relative_error(by_grid, by_faces), tolerance) << gusty;
    EXPECT_EQ(grid_faces, 2u * 149 * 5);
    EXPECT_EQ(loose_faces, grid_faces);
    // The total is three times the sum of the faces' forces.
    Vec3 total{}, total_want{};
    for (std::size_t p = 0; p < want.size(); ++p) total += by_grid[p], total_want += want[p];
    EXPECT_LT(norm(total - total_want), tolerance * norm(total_want)) << gusty;
  }
}

TEST(WindStage, SameBitsOnOneAndTwoThreads) {
  for (const bool as_grid : {true, false}) {
    const Model m = cloth(150, 40, true, as_grid);
    const std::vector<Vec3> one = stage(m, 1), two = stage(m, 2);
    for (std::size_t p = 0; p < one.size(); ++p) ASSERT_EQ(one[p], two[p]) << p << ' ' << as_grid;
  }
}

// A grid group missing one of its faces keeps all its faces on the general path.
TEST(WindStage, IncompleteGridTakesTheGeneralPath) {
  Model m = cloth(12, 5, true, true);
  m.surface.triangles.erase(m.surface.triangles.begin() + 7);
  const std::vector<Vec3> want = law(m);
  Model prepared = m;
  prepared.prepare();
  EXPECT_TRUE(prepared.surface.grids.empty());
  EXPECT_EQ(prepared.surface.loose.size(), m.surface.triangles.size());
  EXPECT_LT(relative_error(stage(m, 1), want), gusty_tolerance);
}

}  // namespace
}  // namespace maille
