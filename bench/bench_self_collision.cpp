// Self-collision broad phases on the crumpled cloth (builders.hpp) of 64^2 to 512^2 particles:
// one full pass (binning, pair tests, exclusion, response forces) per iteration, one thread and
// all threads. Counter "ns_pp": ns per particle per pass. Brute force runs up to 256^2 (64k
// particles: ~2e9 pair tests per pass). Compare ratios within one run.
#include <benchmark/benchmark.h>
#include <omp.h>

#include <vector>

#include "maille/builders.hpp"
#include "maille/self_collision.hpp"

namespace {

using namespace maille;

struct Cloth {
  Model model;
  std::vector<Vec3> x, v, f;
  Real spacing = 0;
};

const Cloth& crumpled(std::uint32_t n) {
  static std::vector<std::pair<std::uint32_t, Cloth>> cache;
  for (const auto& [k, c] : cache)
    if (k == n) return c;
  Cloth c;
  CrumpledClothParams p;
  p.n = n;
  build_crumpled_cloth(c.model, p, "cloth");
  c.model.prepare();
  c.x.assign(c.model.points.initial_position.begin(), c.model.points.initial_position.end());
  c.v.assign(c.x.size(), Vec3{});
  c.f.assign(c.x.size(), Vec3{});
  c.spacing = p.size / Real(n - 1);
  cache.push_back({n, std::move(c)});
  return cache.back().second;
}

// range(0): side n; range(1): broad phase; range(2): threads (0: all); range(3): exclusion.
void BM_SelfCollision(benchmark::State& st) {
  const auto n = static_cast<std::uint32_t>(st.range(0));
  const auto broad = static_cast<BroadPhase>(st.range(1));
  const int threads = st.range(2) == 0 ? omp_get_num_procs() : static_cast<int>(st.range(2));
  const auto exclusion = static_cast<Exclusion>(st.range(3));
  if (broad == BroadPhase::brute && n > 256) {
    st.SkipWithError("brute force skipped above 256^2");
    return;
  }
  Cloth& c = const_cast<Cloth&>(crumpled(n));
  SelfCollisionSettings s;
  s.radius = c.spacing;
  s.broad_phase = broad;
  s.exclusion = exclusion;
  SelfCollisionEngine engine(c.model, s);
  // Warm-up: buffers sized, the cell size tuned (auto): the loop measures the steady state.
  SelfCollisionStats last = engine.apply(c.x.data(), c.v.data(), c.f.data(), threads);
  for (auto _ : st) last = engine.apply(c.x.data(), c.v.data(), c.f.data(), threads);
  const double pp = double(st.iterations()) * n * n;
  st.counters["ns_pp"] =
      benchmark::Counter(pp * 1e-9, benchmark::Counter::kIsRate | benchmark::Counter::kInvert);
  st.counters["contacts"] = double(last.contacts);
  st.counters["tested"] = double(last.candidate_pairs);
  st.counters["cell"] = last.cell_size;
  st.counters["threads"] = threads;
  st.SetLabel(std::string(to_string(broad)) + "/" + std::string(to_string(exclusion)));
}

}  // namespace

BENCHMARK(BM_SelfCollision)
    ->ArgsProduct({{64, 128, 256, 512}, {0, 1, 2, 3}, {1, 0}, {2}})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime()
    ->Iterations(3);
BENCHMARK(BM_SelfCollision)
    ->ArgsProduct({{256}, {1}, {1}, {0, 1}})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime()
    ->Iterations(5);
