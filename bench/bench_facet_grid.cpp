// The facet grid of mesh obstacles (src/collision/obstacle/facet_grid.hpp): its build per facet
// and its query per point, on a closed sphere of N triangles with points around the surface
// (what `method = "facets"` asks once per colliding particle and step). The unit tests bound
// the grid's work (cells, visits, entries) instead of timing it; these are its times.
#include <benchmark/benchmark.h>

#include <cmath>
#include <random>
#include <vector>

#include "collision/obstacle/facet_grid.hpp"
#include "maille/mesh.hpp"

namespace {

using namespace maille;

// A UV sphere of radius 1 with about `triangles` faces (closed: the poles are fans).
TriMesh sphere(int triangles) {
  const int rings = std::max(4, int(std::sqrt(double(triangles) / 2)));
  const int segments = 2 * rings;
  const double pi = std::acos(-1.0);
  TriMesh m;
  m.vertices.push_back({0, 1, 0});
  for (int r = 1; r < rings; ++r)
    for (int s = 0; s < segments; ++s) {
      const double th = pi * r / rings, ph = 2 * pi * s / segments;
      m.vertices.push_back({Real(std::sin(th) * std::cos(ph)), Real(std::cos(th)),
                            Real(std::sin(th) * std::sin(ph))});
    }
  m.vertices.push_back({0, -1, 0});
  const auto at = [&](int r, int s) {
    return std::uint32_t(1 + (r - 1) * segments + s % segments);
  };
  const auto bottom = std::uint32_t(m.vertices.size() - 1);
  for (int s = 0; s < segments; ++s) {
    m.triangles.push_back({0, at(1, s + 1), at(1, s)});
    for (int r = 1; r + 1 < rings; ++r) {
      m.triangles.push_back({at(r, s), at(r, s + 1), at(r + 1, s)});
      m.triangles.push_back({at(r, s + 1), at(r + 1, s + 1), at(r + 1, s)});
    }
    m.triangles.push_back({at(rings - 1, s), at(rings - 1, s + 1), bottom});
  }
  return m;
}

void BM_FacetGridBuild(benchmark::State& state) {
  const TriMesh mesh = sphere(int(state.range(0)));
  for (auto _ : state) {
    facets::FacetGrid grid(mesh);
    benchmark::DoNotOptimize(grid.facets().data());
  }
  state.counters["facets"] = double(mesh.triangles.size());
  state.counters["ns_per_facet"] = benchmark::Counter(
      double(mesh.triangles.size()),
      benchmark::Counter::kIsIterationInvariantRate | benchmark::Counter::kInvert);
}
BENCHMARK(BM_FacetGridBuild)
    ->Arg(1 << 10)
    ->Arg(1 << 14)
    ->Arg(1 << 17)
    ->Unit(benchmark::kMicrosecond);

// One query per point: a box of 1 cm around a point within 2 cm of the surface. `moving`
// (range 1 = 1): each query at a new point (a falling cloth); 0: each point asked again with its
// own row kept (a settled cloth: the row's cell answers, most steps).
void BM_FacetGridQuery(benchmark::State& state) {
  const TriMesh mesh = sphere(int(state.range(0)));
  const facets::FacetGrid grid(mesh);
  std::mt19937 rng(7);
  std::normal_distribution<double> dir(0, 1);
  std::uniform_real_distribution<double> off(-0.02, 0.02);
  constexpr int kPoints = 4096;
  std::vector<Vec3> points(kPoints);
  for (Vec3& p : points) {
    const Vec3 d{Real(dir(rng)), Real(dir(rng)), Real(dir(rng))};
    p = d * Real((1 + off(rng)) / double(norm(d)));
  }
  std::vector<facets::FacetGrid::Row> rows(kPoints);
  std::vector<std::uint32_t> scratch;
  const Vec3 half{Real(0.005), Real(0.005), Real(0.005)};
  const bool moving = state.range(1) == 1;
  std::size_t k = 0, found = 0;
  for (auto _ : state) {
    const std::size_t i = k++ % kPoints;
    facets::FacetGrid::Row fresh;
    auto& row = moving ? fresh : rows[i];
    found += grid.candidates(points[i] - half, points[i] + half, scratch, row).size();
  }
  benchmark::DoNotOptimize(found);
  state.counters["facets"] = double(mesh.triangles.size());
  state.counters["candidates_per_query"] = double(found) / double(state.iterations());
}
BENCHMARK(BM_FacetGridQuery)
    ->ArgsProduct({{1 << 10, 1 << 14, 1 << 17}, {0, 1}})
    ->ArgNames({"facets", "moving"});

}  // namespace
