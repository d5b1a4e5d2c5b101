// The facet grid of the inverse-dynamics stage (src/collision/obstacle/facet_grid.hpp) lists a
// facet only in the cells the triangle meets (a separating-axis test, not its box). What the
// stage relies on: every facet that meets a query box is among the box's candidates, through
// the row a particle keeps (one cell, asked again) and through the several-cell gather. Checked
// by an independent test: points sampled on each facet (vertices, edges, a barycentric lattice)
// that fall in the box, against random boxes from a particle's size to several cells, on closed
// shapes and on a soup of random triangles (slivers, tiny and large ones).
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <random>
#include <string>
#include <vector>

#include "collision/obstacle/facet_grid.hpp"
#include "maille/mesh.hpp"

namespace {

using namespace maille;
using facets::FacetGrid;

// Points of facet f: its vertices and a barycentric lattice (edges included).
std::vector<Vec3> samples(const facets::Facet& f) {
  constexpr int kSteps = 10;
  std::vector<Vec3> out;
  for (int i = 0; i <= kSteps; ++i)
    for (int j = 0; i + j <= kSteps; ++j)
      out.push_back(f.a + f.e1 * (Real(i) / kSteps) + f.e2 * (Real(j) / kSteps));
  return out;
}

bool in_box(const Vec3& p, const Vec3& lo, const Vec3& hi) {
  return p.x >= lo.x && p.y >= lo.y && p.z >= lo.z && p.x <= hi.x && p.y <= hi.y && p.z <= hi.z;
}

TriMesh random_soup(std::mt19937& rng, int count) {
  std::uniform_real_distribution<Real> at(-1, 1), size(-0.3, 0.3);
  TriMesh m;
  for (int t = 0; t < count; ++t) {
    const Vec3 a{at(rng), at(rng), at(rng)};
    const Real s = t % 3 == 0 ? Real(0.01) : Real(1);  // a third of them tiny
    Vec3 b = a + Vec3{size(rng), size(rng), size(rng)} * s;
    Vec3 c = a + Vec3{size(rng), size(rng), size(rng)} * s;
    if (t % 5 == 0) c = a + (b - a) * Real(0.5) + Vec3{1e-4, 0, 0} * s;  // slivers
    const auto base = static_cast<std::uint32_t>(m.vertices.size());
    m.vertices.insert(m.vertices.end(), {a, b, c});
    m.triangles.push_back({base, base + 1, base + 2});
  }
  return m;
}

// Every facet with a sample in a random box is a candidate of that box. Returns the mean
// number of candidates of the smallest boxes (a particle's), for the report.
double check_candidates(const TriMesh& mesh, std::mt19937& rng) {
  const FacetGrid grid(mesh);
  std::vector<std::vector<Vec3>> points;
  for (const auto& f : grid.facets()) points.push_back(samples(f));
  const Vec3 lo = grid.lo(), hi = grid.hi();
  std::uniform_real_distribution<Real> unit(0, 1);
  std::vector<std::uint32_t> scratch;
  FacetGrid::Row row;
  int missed = 0;
  double small_total = 0;
  int small_count = 0;
  for (int q = 0; q < 3000; ++q) {
    // Centred on a facet's sample half the time (boxes that touch the surface), else anywhere.
    Vec3 centre{lo.x + (hi.x - lo.x) * unit(rng), lo.y + (hi.y - lo.y) * unit(rng),
                lo.z + (hi.z - lo.z) * unit(rng)};
    if (q % 2 == 0) {
      const auto& ps = points[std::size_t(unit(rng) * Real(points.size() - 1))];
      centre = ps[std::size_t(unit(rng) * Real(ps.size() - 1))];
    }
    const Real half = (hi.x - lo.x) * std::pow(Real(10), -4 + 3.5 * unit(rng));
    const Vec3 blo = centre - Vec3{1, 1, 1} * half, bhi = centre + Vec3{1, 1, 1} * half;
    for (int ask = 0; ask < 2; ++ask) {  // the second time through the row, when one cell
      const auto near = grid.candidates(blo, bhi, scratch, row);
      std::vector<std::uint32_t> listed(near.begin(), near.end());
      std::sort(listed.begin(), listed.end());
      if (ask == 0 && half < (hi.x - lo.x) * Real(1e-3)) {
        small_total += double(listed.size());
        ++small_count;
      }
      for (std::uint32_t f = 0; f < points.size(); ++f) {
        const bool meets = std::any_of(points[f].begin(), points[f].end(),
                                       [&](const Vec3& p) { return in_box(p, blo, bhi); });
        if (meets && !std::binary_search(listed.begin(), listed.end(), f) && ++missed <= 5)
          ADD_FAILURE() << "facet " << f << " meets box " << q << " (half size " << half
                        << ") but is not a candidate";
      }
    }
  }
  return small_count > 0 ? small_total / small_count : 0;
}

TEST(FacetGrid, EveryFacetMeetingABoxIsACandidateOnASphere) {
  std::mt19937 rng(7);
  TriMesh sphere = tessellate(shape_kind("sphere"), 40);
  for (Vec3& v : sphere.vertices) v = Vec3{v.x * 0.4, v.y * 0.4 + 0.3, v.z * 0.4};
  const double mean = check_candidates(sphere, rng);
  // What the separating-axis test buys: a particle's box on this sphere gets 2.14 candidates
  // (deterministic: seeded), against 3.02 when a facet was listed in every cell its box and
  // plane reach. The bound sits between the two.
  EXPECT_LT(mean, 2.6);
  RecordProperty("mean_candidates_small_box", std::to_string(mean));
}

TEST(FacetGrid, EveryFacetMeetingABoxIsACandidateOnATorusAndACube) {
  std::mt19937 rng(11);
  check_candidates(tessellate(shape_kind("torus"), 24, Real(0.3)), rng);
  check_candidates(tessellate(shape_kind("cube"), 16), rng);
}

TEST(FacetGrid, EveryFacetMeetingABoxIsACandidateInATriangleSoup) {
  std::mt19937 rng(3);
  check_candidates(random_soup(rng, 300), rng);
}

// Many small facets set a fine cell; a few large ones across the whole box used to be tested
// against every cell of their boxes (up to 2^24 each: a 24 MB OBJ of 200,000 small and 1,000
// large triangles took 284 s to validate). The build now visits the cells near a facet's plane,
// column by column, within a budget of visits that coarsens the grid when needed: here 40,000
// small and 200 large facets must build within 3 s (the old build was not timed on this mesh),
// and every point of a large facet still finds it among its candidates. The work is bounded,
// not timed (a timed test fails on a busy machine): cells and (cell, facet) tests within the
// budgets, the entries within the tests (its time is for a benchmark: not written yet).
TEST(FacetGrid, AFewLargeFacetsAmongManySmallOnesBuildWithinTheirBudget) {
  std::mt19937 rng(5);
  std::uniform_real_distribution<Real> at(-1, 1), tiny(-0.002, 0.002);
  TriMesh m;
  auto add = [&](const Vec3& a, const Vec3& b, const Vec3& c) {
    const auto base = static_cast<std::uint32_t>(m.vertices.size());
    m.vertices.insert(m.vertices.end(), {a, b, c});
    m.triangles.push_back({base, base + 1, base + 2});
  };
  for (int t = 0; t < 40'000; ++t) {
    const Vec3 a{at(rng), at(rng), at(rng)};
    add(a, a + Vec3{tiny(rng), tiny(rng), tiny(rng)}, a + Vec3{tiny(rng), tiny(rng), tiny(rng)});
  }
  for (int t = 0; t < 200; ++t)  // tilted triangles across the whole box
    add({at(rng), -1, -1}, {1, at(rng), 1}, {-1, 1, at(rng)});
  const FacetGrid grid(m);
  const std::size_t facets = grid.facets().size();
  EXPECT_LE(double(grid.cell_count()), FacetGrid::cell_budget(facets));
  EXPECT_LE(grid.build_visits(), FacetGrid::visit_budget(facets));
  EXPECT_LE(double(grid.entry_count()), grid.build_visits());
  // The budget is what makes it small: 40,200 facets, at most about 7 million tests, against
  // the billions of cells of the large facets' boxes at the small ones' cell size.
  EXPECT_LT(grid.build_visits(), 8e6);
  // The large facets are found wherever they are: points on them, in one-cell boxes.
  std::vector<std::uint32_t> scratch;
  int missed = 0;
  for (std::uint32_t f = 0; f < grid.facets().size(); ++f) {
    if (grid.facets()[f].d00 < Real(0.01)) continue;  // a small one (the grid sorts facets)
    for (const Vec3& p : samples(grid.facets()[f])) {
      FacetGrid::Row row;
      const Vec3 d{1e-4, 1e-4, 1e-4};
      const auto near = grid.candidates(p - d, p + d, scratch, row);
      if (std::find(near.begin(), near.end(), f) == near.end() && ++missed <= 5)
        ADD_FAILURE() << "large facet " << f << " is not a candidate at a point on it";
    }
  }
}

}  // namespace
