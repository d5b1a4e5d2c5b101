// VBD's coarse correction (src/integrators/vbd_coarse.hpp) on the cloth of
// examples/cloth_on_sphere_vbd.toml (400 N/m structural, 120 shear, 2 bending, 0.25 kg) at 64^2
// and 128^2. BM_CoarseFactorise: the numeric factorisation of the coarse matrix, the engine's
// (Eigen's simplicial LDL^T) against CHOLMOD's supernodal Cholesky and its simplicial LDL^T on
// the same matrix (where Debian's libsuitesparse-dev is installed: MAILLE_HAVE_CHOLMOD), the
// pattern analysed once in each, as the engine keeps it; counter "rel_diff": the largest
// difference of CHOLMOD's solution from Eigen's over Eigen's largest entry. BM_CoarsePrepare
// (the coarse matrix assembled and factorised), BM_CoarseDirection (the solve, two smoothings
// and the curvature) and BM_CoarseBuild (aggregation, pattern, ordering, symbolic analysis:
// what keeping the pattern across steps saves) give the factorisation's share of a correction.
// A Cholesky's cost depends on the pattern alone, so the links' blocks are stand-ins of the
// right sparsity: -k I per link, the diagonal m/h^2 I plus the sum (positive definite).
// Compare ratios within one run.
#include <benchmark/benchmark.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "integrators/vbd_coarse.hpp"
#include "maille/builders.hpp"

#if defined(MAILLE_HAVE_CHOLMOD)
#include "coarse_cholmod.hpp"
#endif

namespace {

using namespace maille;

constexpr Real kStiffness = 400;

struct Cloth {
  Model model;
  std::vector<std::uint32_t> free;
  std::vector<Mat3> diag;
  CoarseCorrection coarse;
};

// The cloth of side n with its coarse correction built and its matrix assembled (made once).
Cloth& cloth(int n) {
  static std::vector<std::pair<int, std::unique_ptr<Cloth>>> cache;
  for (auto& [side, c] : cache)
    if (side == n) return *c;
  auto c = std::make_unique<Cloth>();
  FlagParams p;
  p.nx = p.ny = std::uint32_t(n);
  p.width = p.height = 1;
  p.mass = Real(0.25);
  p.material = {kStiffness, Real(0.02)};
  p.shear_stiffness = 120;
  p.bending_stiffness = 2;
  p.fixed = FlagFixed::none;
  build_flag(c->model, p, "cloth");
  const std::size_t points = c->model.points.inv_mass.size();
  for (std::uint32_t i = 0; i < points; ++i)
    if (c->model.points.inv_mass[i] > 0) c->free.push_back(i);
  const Real h = Real(1) / 60, m = p.mass / Real(points);
  c->diag.assign(points, Mat3::identity() * (m / (h * h)));
  for (const auto& pool : c->model.links.pools())
    for (const LinkEnds& e : pool->slot_ends()) {
      c->diag[e.a] += Mat3::identity() * kStiffness;
      c->diag[e.b] += Mat3::identity() * kStiffness;
    }
  c->coarse.build(c->model, c->free, points);
  for (const auto& pool : c->model.links.pools())
    if (Mat3* b = c->coarse.blocks_of(pool.get()))
      std::fill_n(b, pool->slot_ends().size(), Mat3::identity() * kStiffness);
  if (!c->coarse.prepare(c->diag.data())) throw std::runtime_error("not positive definite");
  cache.emplace_back(n, std::move(c));
  return *cache.back().second;
}

// range(1): 0 the engine's factorisation (Eigen's LDL^T), 1 CHOLMOD supernodal, 2 CHOLMOD
// simplicial.
void BM_CoarseFactorise(benchmark::State& st) {
  Cloth& c = cloth(int(st.range(0)));
  st.counters["aggregates"] = double(c.coarse.aggregates());
  if (st.range(1) == 0) {
    for (auto _ : st) benchmark::DoNotOptimize(c.coarse.factorise());
    return;
  }
#if defined(MAILLE_HAVE_CHOLMOD)
  const CoarseCorrection::Matrix a = c.coarse.matrix();
  CholmodFactor f(st.range(1) == 1);
  if (!f.analyse(a.n, a.column_start, a.rows) || !f.factor(a.values)) {
    st.SkipWithError("CHOLMOD failed");
    return;
  }
  for (auto _ : st) benchmark::DoNotOptimize(f.factor(a.values));
  // The same solution as the engine's: x = A^-1 b for b = A 1 (upper triangle mirrored).
  std::vector<double> b(std::size_t(a.n), 0.0), x(b.size()), y(b.size());
  for (int col = 0; col < a.n; ++col)
    for (int k = a.column_start[col]; k < a.column_start[col + 1]; ++k) {
      b[std::size_t(a.rows[k])] += a.values[k];
      if (a.rows[k] != col) b[std::size_t(col)] += a.values[k];
    }
  f.solve(b.data(), x.data());
  double diff = 0, largest = 0;
  for (const double v : x)
    diff = std::max(diff, std::abs(v - 1.0)), largest = std::max(largest, std::abs(v));
  st.counters["rel_diff"] = diff / largest;
#else
  st.SkipWithError("CHOLMOD is not installed (libsuitesparse-dev)");
#endif
}

void BM_CoarsePrepare(benchmark::State& st) {
  Cloth& c = cloth(int(st.range(0)));
  for (auto _ : st) benchmark::DoNotOptimize(c.coarse.prepare(c.diag.data()));
}

void BM_CoarseDirection(benchmark::State& st) {
  Cloth& c = cloth(int(st.range(0)));
  std::vector<Vec3> g(c.diag.size(), Vec3{0, -1, 0}), p(c.diag.size());
  for (auto _ : st) benchmark::DoNotOptimize(c.coarse.direction(g.data(), p.data()));
}

void BM_CoarseBuild(benchmark::State& st) {
  Cloth& c = cloth(int(st.range(0)));
  for (auto _ : st) {
    CoarseCorrection cc;
    cc.build(c.model, c.free, c.diag.size());
    benchmark::DoNotOptimize(cc.aggregates());
  }
}

}  // namespace

BENCHMARK(BM_CoarseFactorise)->ArgsProduct({{64, 128}, {0, 1, 2}})->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_CoarsePrepare)->Arg(64)->Arg(128)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_CoarseDirection)->Arg(64)->Arg(128)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_CoarseBuild)->Arg(64)->Arg(128)->Unit(benchmark::kMillisecond);
