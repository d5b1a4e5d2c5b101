// Force-and-integrate step of the flag (springs with damping, gravity, leapfrog; no wind, no
// collisions) at 32^2 to 2048^2 points, one thread and all threads.
// Reports ns per particle-step as the counter "ns_pps".
#include <benchmark/benchmark.h>
#include <omp.h>

#include "maille/builders.hpp"
#include "maille/simulator.hpp"

namespace {

maille::Model flag_model(std::uint32_t n) {
  maille::Model m;
  maille::FlagParams p;
  p.nx = p.ny = n;
  p.width = p.height = 1;
  p.mass = 0.2;
  p.material = {200, 0.02};
  p.shear_stiffness = 100;
  p.bending_stiffness = 20;
  maille::build_flag(m, p, "flag");
  return m;
}

// `structured`: the grid links in the structured kernel (the default), else every link on the
// general schedule (Model::structured_grids = false), to compare the two paths.
void flag_step(benchmark::State& st, bool structured) {
  const auto n = static_cast<std::uint32_t>(st.range(0));
  const int threads = st.range(1) == 0 ? omp_get_num_procs() : static_cast<int>(st.range(1));
  maille::SimulationSettings s;
  s.step = 1e-5;  // far inside the stability limit at every size
  s.threads = threads;
  s.publish_every = maille::kNeverEvery;
  s.sample_every = maille::kNeverEvery;
  maille::Model m = flag_model(n);
  m.structured_grids = structured;
  maille::Simulator sim(std::move(m), s);
  for (auto _ : st) sim.step();
  const double ps = double(st.iterations()) * n * n;
  // An inverted rate is seconds per unit: per 1e-9 particle-steps, ns per particle-step.
  st.counters["ns_pps"] =
      benchmark::Counter(ps * 1e-9, benchmark::Counter::kIsRate | benchmark::Counter::kInvert);
  st.counters["threads"] = threads;
}

void BM_FlagStep(benchmark::State& st) {
  flag_step(st, true);
}
void BM_FlagStepGeneral(benchmark::State& st) {
  flag_step(st, false);
}

}  // namespace

// One thread: ns_pps from CPU time (comparable with the reference loops of bench_baselines.cpp
// on a busy machine); all threads: from wall time (what the threads buy).
BENCHMARK(BM_FlagStep)->ArgsProduct({{32, 64, 128, 512}, {1}})->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_FlagStep)
    ->ArgsProduct({{32, 64, 128, 512}, {0}})
    ->Unit(benchmark::kMicrosecond)
    ->UseRealTime();
// 2048^2 (4.2 M points, 25 M links: about 2 GB with the schedule) runs a few steps per repetition.
BENCHMARK(BM_FlagStep)->Args({2048, 1})->Iterations(3)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_FlagStep)
    ->Args({2048, 0})
    ->Iterations(3)
    ->Unit(benchmark::kMicrosecond)
    ->UseRealTime();
// The general path on the same flags (one thread, CPU time), for the table of both paths.
BENCHMARK(BM_FlagStepGeneral)->ArgsProduct({{64, 128, 512}, {1}})->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_FlagStepGeneral)->Args({2048, 1})->Iterations(3)->Unit(benchmark::kMicrosecond);
