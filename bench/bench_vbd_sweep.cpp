// One VBD sweep on the cloth resting on the sphere (the peer harness's scene, bench/peer: a 1 m,
// 0.3 kg cloth of 2000 N/m structural and 500 N/m shear spring-dampers on a geometric sphere)
// at 64^2 and 128^2, one thread, 1/60 s: the scalar sweep (1 lane) against the lanes at each
// width the CPU runs (src/integrators/vbd_lanes.hpp). The cloth falls for 2 s at the default
// settings first (10 sweeps and the coarse correction), then every iteration times the step
// from that resting state with 1 sweep and with 11 (coarse correction and acceleration off, so
// that the steps differ by 10 sweeps alone): counter "ns_point_sweep" is their difference over
// 10 sweeps and the points. Compare ratios within one run.
#include <benchmark/benchmark.h>

#include <cstring>
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

#if defined(MAILLE_HAVE_HWY)
}  // namespace
namespace maille::vbd_lanes {
const Kernels* highway_kernels();  // bench_vbd_dispatch_hwy.cpp
const char* highway_target();
void highway_terms(const Block& b, const Rows& rows, const Step& s, Real* g, Real* h);
}  // namespace maille::vbd_lanes
namespace {

// The positions after one step of 11 sweeps from the resting state with the kernels in use.
std::vector<Vec3> stepped(Resting& r) {
  timed_step(*r.sim, r.rest, 11);
  const auto x = r.sim->state().x();
  return {x.begin(), x.end()};
}

// The same sweeps as BM_VbdSweep at the widest width, the kernels reached through
// vbd_lanes.cpp's table (range(1) = 0) or through Highway's HWY_DYNAMIC_DISPATCH at every call
// (1). Counter "same_bits": 1 when a step by Highway's kernels gives the table's positions
// bit for bit.
void BM_VbdDispatch(benchmark::State& st) {
  const int n = int(st.range(0)), highway = int(st.range(1));
  Resting& r = resting(n);
  set_vbd_lane_width(0);
  set_vbd_lane_kernels(highway ? vbd_lanes::highway_kernels() : nullptr);
  double sweeps_seconds = 0;
  for (auto _ : st) {
    const double one = timed_step(*r.sim, r.rest, 1);
    const double eleven = timed_step(*r.sim, r.rest, 11);
    st.SetIterationTime(eleven - one);
    sweeps_seconds += eleven - one;
  }
  const int width = vbd_lane_width();
  set_vbd_lane_kernels(nullptr);
  const double points = double(r.sim->state().size());
  st.counters["ns_point_sweep"] = sweeps_seconds * 1e9 / (double(st.iterations()) * 10 * points);
  st.counters["lanes"] = width;
  if (highway) {
    const std::vector<Vec3> table = stepped(r);
    set_vbd_lane_kernels(vbd_lanes::highway_kernels());
    const std::vector<Vec3> hwy = stepped(r);
    set_vbd_lane_kernels(nullptr);
    st.counters["same_bits"] =
        std::memcmp(table.data(), hwy.data(), table.size() * sizeof(Vec3)) == 0 ? 1 : 0;
    st.SetLabel(vbd_lanes::highway_target());
  }
}

// One kernel call on a block of points without links (inertia and drag only), so that the
// dispatch's own cost shows: the table's function pointer as VbdLanes calls it (range(0) = 0)
// against HWY_DYNAMIC_DISPATCH at the call (1).
void BM_VbdDispatchCall(benchmark::State& st) {
  set_vbd_lane_kernels(nullptr);
  set_vbd_lane_width(0);
  const vbd_lanes::Kernels* table = vbd_lane_kernels();
  const int w = table ? table->width : 0;
  if (w != vbd_lanes::highway_kernels()->width) {
    st.SkipWithError("the table and Highway chose different widths");
    return;
  }
  std::vector<std::uint32_t> pts(static_cast<std::size_t>(w));
  for (int l = 0; l < w; ++l) pts[std::size_t(l)] = std::uint32_t(l);
  std::vector<Real> x(3 * std::size_t(w), 1), v(x), y(x), g(x), mass(std::size_t(w), 1),
      h(9 * std::size_t(w), 0);
  const vbd_lanes::Step s{x.data(), v.data(), y.data(), mass.data(), 60, 3600, 0};
  const vbd_lanes::Block b{pts.data(), std::uint32_t(w), 0, 0, nullptr, nullptr};
  const vbd_lanes::Rows rows{nullptr, nullptr};
  if (st.range(0)) {
    for (auto _ : st) {
      vbd_lanes::highway_terms(b, rows, s, g.data(), h.data());
      benchmark::DoNotOptimize(g.data());
      benchmark::ClobberMemory();
    }
  } else {
    for (auto _ : st) {
      table->terms(b, rows, s, g.data(), h.data());
      benchmark::DoNotOptimize(g.data());
      benchmark::ClobberMemory();
    }
  }
  st.counters["lanes"] = w;
}
#endif

}  // namespace

BENCHMARK(BM_VbdSweep)
    ->ArgsProduct({{64, 128}, {1, 2, 4, 8}})
    ->UseManualTime()
    ->Unit(benchmark::kMillisecond);
#if defined(MAILLE_HAVE_HWY)
BENCHMARK(BM_VbdDispatch)
    ->ArgsProduct({{64, 128}, {0, 1}})
    ->UseManualTime()
    ->Unit(benchmark::kMillisecond);
BENCHMARK(BM_VbdDispatchCall)->Arg(0)->Arg(1);
#endif
