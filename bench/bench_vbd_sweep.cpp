// One VBD sweep on the cloth resting on the sphere (the peer harness's scene, bench/peer: a 1 m,
// 0.3 kg cloth of 2000 N/m structural and 500 N/m shear spring-dampers on a geometric sphere)
// at 64^2 and 128^2, one thread, 1/60 s: the scalar sweep (1 lane) against the lanes at each
// width the CPU runs (src/integrators/vbd_lanes.hpp). The cloth falls for 2 s at the default
// settings first (10 sweeps and the coarse correction), then every iteration times the step
// from that resting state with 1 sweep and with 11 (coarse correction and acceleration off, so
// that the steps differ by 10 sweeps alone): counter "ns_point_sweep" is their difference over
// 10 sweeps and the points. Compare ratios within one run.
#include <benchmark/benchmark.h>

#include <sstream>
#include <string>
#include <vector>

#include "integrators/vbd_lanes.hpp"
#include "maille/clock.hpp"
#include "maille/link_registry.hpp"
#include "maille/scene.hpp"
#include "maille/simulator.hpp"
#include "maille/stage_registry.hpp"

namespace {

using namespace maille;

std::string sphere_scene(int n) {
  std::ostringstream t;
  t << "[simulation]\nintegrator = \"implicit_euler\"\nstep = 0.016666666666666666\n"
    << "[simulation.implicit]\nsolver = \"vbd\"\n"
    << "[fields]\ngravity = [0.0, -9.81, 0.0]\n"
    << "[[flag]]\nname = \"cloth\"\norigin = [-0.5, 0.75, -0.5]\nalong = [1.0, 0.0, 0.0]\n"
    << "up = [0.0, 0.0, 1.0]\nwidth = 1.0\nheight = 1.0\nresolution = [" << n << ", " << n
    << "]\nmass = 0.3\nstiffness = 2000.0\nshear_stiffness = 500.0\nbending_stiffness = 0.0\n"
    << "damping = 0.02\nfixed = \"none\"\n"
    << "[[obstacle]]\nname = \"ball\"\nshape = \"sphere\"\nmethod = \"geometric\"\n"
    << "scale = [0.25, 0.25, 0.25]\ncollides_with = [\"cloth\"]\n";
  return t.str();
}

struct Resting {
  int n = 0;
  std::unique_ptr<Simulator> sim;
  State rest;
};

// The simulator of side n after 2 s, and its state then (made once per side).
Resting& resting(int n) {
  static std::vector<std::unique_ptr<Resting>> cache;
  for (auto& r : cache)
    if (r->n == n) return *r;
  const auto kinds = LinkKindRegistry::with_builtins();
  const auto stages = StageRegistry::with_builtins();
  auto scene = parse_scene(sphere_scene(n), "bench_vbd_sweep", kinds, stages);
  if (!scene.ok()) throw std::runtime_error(scene.error().to_string());
  scene->settings.threads = 1;
  scene->settings.backend = "cpu";
  auto r = std::make_unique<Resting>();
  r->n = n;
  r->sim = std::make_unique<Simulator>(std::move(scene->model), scene->settings);
  set_vbd_lane_width(0);
  r->sim->run_steps(120);
  r->rest = r->sim->state();
  cache.push_back(std::move(r));
  return *cache.back();
}

double timed_step(Simulator& sim, const State& from, int sweeps) {
  ImplicitSettings s;
  s.solver = ImplicitSolver::vbd;
  s.iterations = sweeps;
  s.acceleration = 0;
  s.coarse = VbdCoarse::off;
  sim.set_implicit(s);
  sim.restore(from);
  const auto t0 = WallClock::now();
  sim.step();
  return seconds_since(t0);
}

// range(0): side n; range(1): lanes (1: the scalar sweep).
void BM_VbdSweep(benchmark::State& st) {
  const int n = int(st.range(0)), width = int(st.range(1));
  if (!vbd_lane_width_runs(width)) {
    st.SkipWithError("this CPU cannot run that width");
    return;
  }
  Resting& r = resting(n);
  set_vbd_lane_width(width);
  double sweeps_seconds = 0;
  for (auto _ : st) {
    const double one = timed_step(*r.sim, r.rest, 1);
    const double eleven = timed_step(*r.sim, r.rest, 11);
    st.SetIterationTime(eleven - one);
    sweeps_seconds += eleven - one;
  }
  set_vbd_lane_width(0);
  const double points = double(r.sim->state().size());
  st.counters["ns_point_sweep"] = sweeps_seconds * 1e9 / (double(st.iterations()) * 10 * points);
  st.counters["lanes"] = width;
}

}  // namespace

BENCHMARK(BM_VbdSweep)
    ->ArgsProduct({{64, 128}, {1, 2, 4, 8}})
    ->UseManualTime()
    ->Unit(benchmark::kMillisecond);
