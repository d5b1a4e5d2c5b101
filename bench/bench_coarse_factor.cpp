// VBD's coarse correction (src/integrators/vbd_coarse.hpp) on the cloth of
// examples/cloth_on_sphere_vbd.toml (400 N/m structural, 120 shear, 2 bending, 0.25 kg) at 64^2
// and 128^2: the coarse matrix's assembly and numeric factorisation (prepare), its solve and
// smoothed direction (direction), and the whole set-up (build: aggregation, pattern, ordering,
// symbolic analysis) that keeping the pattern saves, by Eigen's simplicial LDL^T against
// CHOLMOD's supernodal Cholesky (where built in: MAILLE_HAVE_CHOLMOD). A Cholesky's cost
// depends on the pattern alone, so the links' blocks are stand-ins of the right sparsity: -k I
// per link, the diagonal m/h^2 I plus the sum (positive definite). Compare ratios within one run.
#include <benchmark/benchmark.h>

#include <cstdlib>
#include <vector>

#include "integrators/vbd_coarse.hpp"
#include "maille/builders.hpp"

namespace {

using namespace maille;

struct Cloth {
  Model model;
  std::vector<std::uint32_t> free;
  std::vector<Mat3> diag;
};

Cloth cloth(int n) {
  Cloth c;
  FlagParams p;
  p.nx = p.ny = std::uint32_t(n);
  p.width = p.height = 1;
  p.mass = Real(0.25);
  p.material = {400, Real(0.02)};
  p.shear_stiffness = 120;
  p.bending_stiffness = 2;
  p.fixed = FlagFixed::none;
  build_flag(c.model, p, "cloth");
  const std::size_t points = c.model.points.inv_mass.size();
  for (std::uint32_t i = 0; i < points; ++i)
    if (c.model.points.inv_mass[i] > 0) c.free.push_back(i);
  const Real h = Real(1) / 60, m = p.mass / Real(points);
  c.diag.assign(points, Mat3::identity() * (m / (h * h)));
  for (const auto& pool : c.model.links.pools())
    for (const LinkEnds& e : pool->slot_ends()) {
      c.diag[e.a] += Mat3::identity() * Real(400);
      c.diag[e.b] += Mat3::identity() * Real(400);
    }
  return c;
}

// factor 0: Eigen's LDL^T, 1: CHOLMOD (vbd_coarse.cpp reads MAILLE_COARSE_FACTOR in build).
bool choose(benchmark::State& st, int factor) {
#if !defined(MAILLE_HAVE_CHOLMOD)
  if (factor == 1) {
    st.SkipWithError("CHOLMOD is not built in");
    return false;
  }
#else
  (void)st;
#endif
  setenv("MAILLE_COARSE_FACTOR", factor == 1 ? "cholmod" : "ldlt", 1);
  return true;
}

void fill(CoarseCorrection& cc, const Model& m) {
  for (const auto& pool : m.links.pools())
    if (Mat3* b = cc.blocks_of(pool.get()))
      for (std::size_t l = 0; l < pool->slot_ends().size(); ++l) b[l] = Mat3::identity() * Real(400);
}

void BM_CoarsePrepare(benchmark::State& st) {
  if (!choose(st, int(st.range(1)))) return;
  const Cloth c = cloth(int(st.range(0)));
  CoarseCorrection cc;
  cc.build(c.model, c.free, c.diag.size());
  fill(cc, c.model);
  for (auto _ : st) benchmark::DoNotOptimize(cc.prepare(c.diag.data()));
  st.counters["aggregates"] = double(cc.aggregates());
}

// The numeric factorisation alone (the matrix assembled once).
void BM_CoarseFactorise(benchmark::State& st) {
  if (!choose(st, int(st.range(1)))) return;
  const Cloth c = cloth(int(st.range(0)));
  CoarseCorrection cc;
  cc.build(c.model, c.free, c.diag.size());
  fill(cc, c.model);
  if (!cc.prepare(c.diag.data())) {
    st.SkipWithError("not positive definite");
    return;
  }
  for (auto _ : st) benchmark::DoNotOptimize(cc.factorise());
  st.counters["aggregates"] = double(cc.aggregates());
}

void BM_CoarseDirection(benchmark::State& st) {
  if (!choose(st, int(st.range(1)))) return;
  const Cloth c = cloth(int(st.range(0)));
  CoarseCorrection cc;
  cc.build(c.model, c.free, c.diag.size());
  fill(cc, c.model);
  if (!cc.prepare(c.diag.data())) {
    st.SkipWithError("not positive definite");
    return;
  }
  std::vector<Vec3> g(c.diag.size(), Vec3{0, -1, 0}), p(c.diag.size());
  for (auto _ : st) benchmark::DoNotOptimize(cc.direction(g.data(), p.data()));
}

void BM_CoarseBuild(benchmark::State& st) {
  if (!choose(st, int(st.range(1)))) return;
  const Cloth c = cloth(int(st.range(0)));
  for (auto _ : st) {
    CoarseCorrection cc;
    cc.build(c.model, c.free, c.diag.size());
    benchmark::DoNotOptimize(cc.aggregates());
  }
}

}  // namespace

BENCHMARK(BM_CoarsePrepare)->ArgsProduct({{64, 128}, {0, 1}})->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_CoarseFactorise)->ArgsProduct({{64, 128}, {0, 1}})->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_CoarseDirection)->ArgsProduct({{64, 128}, {0, 1}})->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_CoarseBuild)->ArgsProduct({{64, 128}, {0, 1}})->Unit(benchmark::kMillisecond);
