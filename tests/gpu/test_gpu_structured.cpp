// The GPU's structured layout for grid cloth (src/gpu/gpu_structured.hpp) against the general
// layout and the CPU.
//
// The stated bound. Both layouts evaluate each link with the same shared law on the same floats
// and sum a point's forces in the same order (the adjacency's slot order, which the stencil
// follows), so they agree bit for bit unless the shader compiler contracts a multiply and an
// add into one fused operation in one kernel and not in the other. A contraction changes one
// rounding of the law: at most eps (2^-24) of the magnitudes the law combines, about
// k (|d| + L0) for a spring and z |dv| for a damper, for each of its c = 8 operations. Per point
// the bound is the sum over its links of 8 eps (k (|d| + L0) + z |dv|) (x2 for the two
// layouts), plus its faces' share (the wind's face forces are the same buffer in both layouts:
// nothing). On llvmpipe the layouts are bit-identical (measured: every point, every test here),
// which the tests record. Whole runs: the structured run stays within the float-storage drift
// of the general one (test_gpu_runs.cpp's yardstick: what rounding x and v to float every step
// does to the trajectory), as per-step differences of the size of float rounding allow.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <random>

#include "gpu/gpu_test_support.hpp"
#include "maille/backend.hpp"
#include "maille/builders.hpp"
#include "maille/gpu.hpp"
#include "maille/links/spring.hpp"
#include "maille/links/spring_damper.hpp"
#include "maille/scene.hpp"
#include "maille/simulator.hpp"

namespace maille {
namespace {

constexpr double kEps = test::kFloatEps;
using GpuStructured = test::GpuTest;

// MAILLE_GPU_LAYOUT for the backends made while it lives.
class Layout {
 public:
  explicit Layout(const char* value) {
    if (const char* old = std::getenv("MAILLE_GPU_LAYOUT")) old_ = old, had_ = true;
    setenv("MAILLE_GPU_LAYOUT", value, 1);
  }
  ~Layout() {
    if (had_)
      setenv("MAILLE_GPU_LAYOUT", old_.c_str(), 1);
    else
      unsetenv("MAILLE_GPU_LAYOUT");
  }
  Layout(const Layout&) = delete;
  Layout& operator=(const Layout&) = delete;

 private:
  std::string old_;
  bool had_ = false;
};

// Mesa's llvmpipe, where the two layouts are measured bit-identical (a GPU's compiler may
// contract differently in the two kernels: the bound then).
bool on_llvmpipe() {
  static const bool yes = [] {
    auto b = BackendRegistry::global().find("gpu")->make(BackendOptions{});
    return b->describe().find("llvmpipe") != std::string::npos;
  }();
  return yes;
}

struct Forces {
  State state;
  std::vector<gpu::StructuredGridInfo> grids;  // those run structured
};

Forces gpu_forces(const Model& m, const State& s, const char* layout) {
  Layout scoped(layout);
  Model prepared = m;
  prepared.prepare();
  auto b = BackendRegistry::global().find("gpu")->make(BackendOptions{});
  b->load(prepared, s);
  b->evaluate(prepared, s.time);
  Forces out{State(s.size()), gpu::structured_grids(*b)};
  b->download(out.state);
  return out;
}

State cpu_forces(const Model& m, const State& s) {
  SimulationSettings settings;
  settings.threads = 1;
  Simulator sim(m, settings);
  sim.restore(s);
  sim.energies();
  return sim.state();
}

// Per point: the header's bound on a contraction's effect, over the point's links, times 2.
std::vector<double> contraction_bounds(const Model& m, const State& s) {
  std::vector<double> bound(s.size(), 0);
  for (const auto& pool : m.links.pools()) {
    const auto fields = pool->fields();
    for (std::size_t id = 0; id < pool->size(); ++id) {
      double k = 0, z = 0, L = 0;
      for (std::size_t f = 0; f < fields.size(); ++f) {
        const double p = pool->param(id, f);
        if (fields[f].name == "stiffness") k = p;
        if (fields[f].name == "damping") z = p;
        if (fields[f].name == "rest_length") L = p;
      }
      const auto [a, b] = pool->ends(id);
      const double d = norm(s.x()[b] - s.x()[a]), dv = norm(s.v()[b] - s.v()[a]);
      const double e = 2 * 8 * kEps * (k * (d + L) + z * dv);
      bound[a] += e;
      bound[b] += e;
    }
  }
  return bound;
}

// Structured against general: within the bound at every point; returns how many points are
// bit-identical (recorded).
std::size_t expect_layouts_agree(const Model& m, const State& s) {
  const Forces structured = gpu_forces(m, s, "structured");
  const Forces general = gpu_forces(m, s, "general");
  EXPECT_FALSE(structured.grids.empty()) << "nothing ran structured";
  EXPECT_TRUE(general.grids.empty());
  const std::vector<double> bound = contraction_bounds(m, s);
  std::size_t identical = 0;
  for (std::size_t i = 0; i < s.size(); ++i) {
    const Vec3 a = structured.state.f()[i], b = general.state.f()[i];
    EXPECT_LE(norm(a - b), bound[i] + 1e-30) << "point " << i;
    identical += a == b;
  }
  ::testing::Test::RecordProperty("bit_identical_points",
                                  std::to_string(identical) + " of " + std::to_string(s.size()));
  std::printf("bit-identical forces: %zu of %zu points\n", identical, s.size());
  return identical;
}

// The CPU's force bound of test_gpu_backend.cpp (float storage and arithmetic, per link),
// without wind: |f_gpu - f_cpu| within it at every point.
void expect_near_the_cpu(const Model& m, const State& s, const State& gpu) {
  const State cpu = cpu_forces(m, s);
  const double X = test::max_abs(s.x()), V = test::max_norm(s.v());
  std::vector<double> bound(s.size(), 0);
  for (const auto& pool : m.links.pools()) {
    const auto fields = pool->fields();
    for (std::size_t id = 0; id < pool->size(); ++id) {
      double k = 0, z = 0, L = 0;
      for (std::size_t f = 0; f < fields.size(); ++f) {
        const double p = pool->param(id, f);
        if (fields[f].name == "stiffness") k = p;
        if (fields[f].name == "damping") z = p;
        if (fields[f].name == "rest_length") L = p;
      }
      const auto [a, b] = pool->ends(id);
      const double d = norm(s.x()[b] - s.x()[a]), dv = norm(s.v()[b] - s.v()[a]);
      const double e = 4 * kEps * (k * (2 * X + 8 * (d + L)) + z * (2 * V + 8 * dv));
      bound[a] += e;
      bound[b] += e;
    }
  }
  for (std::size_t i = 0; i < s.size(); ++i) {
    const double fields =
        4 * kEps * m.points.mass[i] * (norm(m.fields.gravity) + m.fields.air_drag * norm(s.v()[i]));
    EXPECT_LE(norm(gpu.f()[i] - cpu.f()[i]), bound[i] + fields + 1e-30) << "point " << i;
  }
}

Model flag(std::uint32_t nx, std::uint32_t ny) {
  Model m;
  FlagParams p;
  p.nx = nx;
  p.ny = ny;
  p.material = {200, 0.02};
  p.shear_stiffness = 100;
  p.bending_stiffness = 20;
  build_flag(m, p, "flag");
  return m;
}

// The flag crumpled and moving, so that every link is stretched or compressed.
State crumpled(const Model& m, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<Real> u(-1, 1);
  State s(m.points.size());
  for (std::size_t i = 0; i < s.size(); ++i) {
    s.x()[i] = m.points.initial_position[i] + Vec3{u(rng), u(rng), u(rng)} * Real(0.01);
    s.v()[i] = Vec3{u(rng), u(rng), u(rng)};
  }
  s.time = 0.9;
  return s;
}

TEST_F(GpuStructured, FlagForcesMatchTheGeneralLayoutAndTheCpu) {
  Model m = flag(40, 30);
  m.fields.air_drag = Real(0.2);
  const State s = crumpled(m, 1);
  const std::size_t identical = expect_layouts_agree(m, s);
  if (on_llvmpipe()) {
    EXPECT_EQ(identical, s.size()) << "llvmpipe: bit-identical expected";
  }
  expect_near_the_cpu(m, s, gpu_forces(m, s, "structured").state);
}

TEST_F(GpuStructured, FlagInGustyWindMatchesTheGeneralLayout) {
  Model m = flag(40, 30);
  m.fields.wind.velocity = {6, 0, Real(1.5)};
  m.fields.wind.turbulence = Real(0.5);
  expect_layouts_agree(m, crumpled(m, 2));
}

// Holes (links touching them left out: rows break, stencil bits clear), pinned points inside
// the grid, links off the families and a duplicate (general, after the stencil), a spring pool
// stored before the spring-dampers (its links summed before the stencil) and points off the
// grid on both sides of it (the general kernel's ranges).
Model holed_flag() {
  Model m;
  m.points.add(PointKind::fixed, 1, {Real(-0.2), 1, 0});  // before the grid
  Model whole = flag(36, 28);
  m.links.pool<Spring>();  // first pool
  const std::uint32_t base = 1;
  for (std::size_t i = 0; i < whole.points.size(); ++i)
    m.points.add(whole.points.kind[i], whole.points.mass[i], whole.points.initial_position[i]);
  for (Group g : whole.groups) {
    g.first += base;
    m.groups.push_back(g);
  }
  for (auto t : whole.surface.triangles)
    m.surface.triangles.push_back({t[0] + base, t[1] + base, t[2] + base});
  const auto& pool = whole.links.pool<SpringDamper>();
  auto in_hole = [](std::uint32_t p) {
    const int i = int(p % 36), j = int(p / 36);
    return (i - 18) * (i - 18) + (j - 14) * (j - 14) < 20 || (i == 6 && j > 3);
  };
  auto& sd = m.links.pool<SpringDamper>();
  for (std::size_t id = 0; id < pool.size(); ++id) {
    const LinkEnds e = pool.ends(id);
    if (in_hole(e.a) || in_hole(e.b)) continue;
    sd.add({e.a + base, e.b + base}, pool.params(id));
  }
  const auto& x = m.points.initial_position;
  auto length = [&](std::uint32_t a, std::uint32_t b) { return norm(x[b] - x[a]); };
  sd.add({base + 0, base + 74}, {50, length(base, base + 74), Real(0.01)});   // (2, 2): off
  sd.add({base + 100, base + 101}, {70, length(base + 100, base + 101), 0});  // a duplicate
  for (std::uint32_t p : {base + 300, base + 301, base + 520})
    m.points.set_kind(p, PointKind::fixed);  // pinned inside the grid
  const std::uint32_t after = m.points.add(PointKind::free, Real(0.01), {Real(0.5), Real(0.2), 0});
  auto& springs = m.links.pool<Spring>();
  springs.add({0, base + 35}, {30, length(0, base + 35)});
  springs.add({after, base + 36 * 27 + 17}, {40, length(after, base + 36 * 27 + 17)});
  springs.add({base + 40, base + 41}, {25, length(base + 40, base + 41) * Real(0.9)});
  return m;
}

TEST_F(GpuStructured, HolesPinnedPointsAndOtherLinks) {
  const Model m = holed_flag();
  ASSERT_EQ(m.links.pools().front()->keyword(), "spring");
  const State s = crumpled(m, 3);
  const std::size_t identical = expect_layouts_agree(m, s);
  if (on_llvmpipe()) {
    EXPECT_EQ(identical, s.size()) << "llvmpipe: bit-identical expected";
  }
  expect_near_the_cpu(m, s, gpu_forces(m, s, "structured").state);
}

// Whole runs: structured within the float-storage drift of general; both against the CPU.
std::vector<Vec3> run(const Model& m, SimulationSettings settings, const char* backend,
                      std::uint64_t steps, bool float_storage = false) {
  settings.backend = backend;
  settings.threads = 1;
  Simulator sim(m, settings);
  for (std::uint64_t k = 0; k < steps; ++k) {
    EXPECT_TRUE(sim.step()) << backend << " step " << k;
    if (float_storage) test::round_to_float(sim.state_for_editing());
  }
  return {sim.state().x().begin(), sim.state().x().end()};
}

void expect_runs_agree(const Model& m, const SimulationSettings& settings, std::uint64_t steps) {
  const auto cpu = run(m, settings, "cpu", steps);
  const auto rounded = run(m, settings, "cpu", steps, true);
  std::vector<Vec3> structured, general;
  {
    Layout l("structured");
    structured = run(m, settings, "gpu", steps);
  }
  {
    Layout l("general");
    general = run(m, settings, "gpu", steps);
  }
  const double drift = test::max_distance(cpu, rounded);
  const double between = test::max_distance(structured, general);
  std::printf("structured - general %.3g m, structured - cpu %.3g m, float-storage drift %.3g m\n",
              between, test::max_distance(structured, cpu), drift);
  EXPECT_GT(drift, 0.0);
  EXPECT_LE(between, drift);
  EXPECT_LE(test::max_distance(structured, cpu), 4 * drift + 1e-6);
}

TEST_F(GpuStructured, FlagInWindRunsAgree) {
  const Scene scene = test::example_scene("flag_in_wind");
  expect_runs_agree(scene.model, scene.settings, 300);
}

TEST_F(GpuStructured, HoledFlagRunsAgree) {
  SimulationSettings settings;
  settings.step = 2e-4;
  expect_runs_agree(holed_flag(), settings, 300);
}

// Every example with a grid that the GPU runs (obstacles and broad-phase contacts are refused):
// 30 steps, structured within the float-storage drift of general (bit-identical on llvmpipe).
TEST_F(GpuStructured, EveryGridExampleTheGpuRuns) {
  int ran = 0;
  for (const auto& entry : std::filesystem::directory_iterator(MAILLE_SOURCE_DIR "/examples")) {
    if (entry.path().extension() != ".toml") continue;
    const Scene scene = test::example_scene(entry.path().stem().string());
    if (point_grids(scene.model).empty() || scene.model.points.size() > 100000) continue;
    SimulationSettings settings = scene.settings;
    settings.backend = "gpu";
    try {
      Simulator probe(scene.model, settings);
    } catch (const std::invalid_argument&) {
      continue;  // refused by name (test_gpu_runs.cpp checks refusals)
    }
    const std::uint64_t steps = 30;
    std::vector<Vec3> structured, general;
    {
      Layout l("structured");
      structured = run(scene.model, scene.settings, "gpu", steps);
    }
    {
      Layout l("general");
      general = run(scene.model, scene.settings, "gpu", steps);
    }
    const auto cpu = run(scene.model, scene.settings, "cpu", steps);
    const auto rounded = run(scene.model, scene.settings, "cpu", steps, true);
    const double between = test::max_distance(structured, general);
    const double drift = test::max_distance(cpu, rounded);
    EXPECT_LE(between, drift) << entry.path().filename();
    std::printf("%s: structured - general %.3g m (float-storage drift %.3g m)\n",
                entry.path().stem().string().c_str(), between, drift);
    ++ran;
  }
  EXPECT_GE(ran, 5);
}

// Two grids with a point between them: one dispatch each, the point by the general kernel.
TEST_F(GpuStructured, TwoGridsAndAPointBetween) {
  Model m = flag(20, 16);
  m.points.add(PointKind::free, Real(0.01), {Real(-0.3), Real(0.5), 0});
  FlagParams second;
  second.nx = 24;
  second.ny = 12;
  second.origin = {0, 0, 1};
  second.material = {150, 0.01};
  build_flag(m, second, "second");
  const auto& x = m.points.initial_position;
  const std::uint32_t lone = 20 * 16;
  m.links.pool<Spring>().add({lone, 5}, {40, norm(x[5] - x[lone])});
  m.links.pool<Spring>().add({lone, lone + 30}, {40, norm(x[lone + 30] - x[lone])});
  const State s = crumpled(m, 5);
  expect_layouts_agree(m, s);
  const auto grids = gpu_forces(m, s, "structured").grids;
  ASSERT_EQ(grids.size(), 2u);
  EXPECT_EQ(grids[1].first, lone + 1);
  EXPECT_EQ(grids[1].nx, 24u);
}

// Edits between steps reload the device: one link's stiffness and another's rest length (their
// families turn per link), then every link scaled (uniform again), then a structural edit (a
// pinned point and a new link). The two layouts stay together, and near the CPU.
TEST_F(GpuStructured, ParameterAndModelEditsReloadTheDevice) {
  const Model m = flag(32, 24);
  SimulationSettings settings;
  settings.step = 2e-4;
  auto edited = [&](const char* backend) {
    SimulationSettings s = settings;
    s.backend = backend;
    s.threads = 1;
    Simulator sim(m, s);
    sim.run_steps(40);
    sim.edit_parameters([](Model& model) {
      auto& p = model.links.pool<SpringDamper>();
      p.params_for_editing(40).stiffness *= 3;
      p.params_for_editing(41).rest_length *= Real(0.9);
    });
    sim.run_steps(40);
    sim.edit_parameters(
        [](Model& model) { model.links.find("spring_damper")->scale_param(0, Real(1.5)); });
    sim.run_steps(40);
    sim.edit_model([](Model& model) {
      model.points.set_kind(400, PointKind::fixed);
      const Real d = norm(model.points.initial_position[500] - model.points.initial_position[10]);
      model.links.pool<SpringDamper>().add({10, 500}, {20, d, Real(0.01)});
    });
    sim.run_steps(40);
    return std::vector<Vec3>(sim.state().x().begin(), sim.state().x().end());
  };
  std::vector<Vec3> structured, general;
  {
    Layout l("structured");
    structured = edited("gpu");
  }
  {
    Layout l("general");
    general = edited("gpu");
  }
  const auto cpu = edited("cpu");
  const double between = test::max_distance(structured, general);
  std::printf("after edits: structured - general %.3g m, structured - cpu %.3g m\n", between,
              test::max_distance(structured, cpu));
  if (on_llvmpipe()) {
    EXPECT_EQ(between, 0.0) << "llvmpipe: bit-identical expected";
  }
  EXPECT_LE(between, 1e-5);
  // 160 steps of float storage on a 1 m flag: a few 1e-7 m; 1e-5 m catches a wrong link.
  EXPECT_LE(test::max_distance(structured, cpu), 1e-5);
}

// A model without grids is the general layout, whatever the choice; automatic takes grids of
// kStructuredMinPoints points and leaves smaller ones general.
TEST_F(GpuStructured, WhereItRuns) {
  Model cloud;
  std::mt19937 rng(4);
  std::uniform_real_distribution<Real> u(-1, 1);
  for (int i = 0; i < 300; ++i)
    cloud.points.add(PointKind::free, Real(0.01), {u(rng), u(rng), u(rng)});
  for (std::uint32_t i = 0; i + 1 < 300; ++i)
    cloud.links.pool<SpringDamper>().add({i, i + 1}, {100, Real(0.1), Real(0.01)});
  State s(cloud.points.size());
  for (std::size_t i = 0; i < s.size(); ++i) s.x()[i] = cloud.points.initial_position[i];
  const Forces a = gpu_forces(cloud, s, "structured"), b = gpu_forces(cloud, s, "general");
  EXPECT_TRUE(a.grids.empty());
  for (std::size_t i = 0; i < s.size(); ++i) ASSERT_EQ(a.state.f()[i], b.state.f()[i]) << i;

  const Model small = flag(40, 30), large = flag(64, 64);
  State ss(small.points.size()), sl(large.points.size());
  EXPECT_TRUE(gpu_forces(small, ss, "auto").grids.empty());
  EXPECT_EQ(gpu_forces(small, ss, "structured").grids.size(), 1u);
  const auto taken = gpu_forces(large, sl, "auto").grids;
  ASSERT_EQ(taken.size(), 1u);
  EXPECT_EQ(taken[0].nx, 64u);
  EXPECT_EQ(taken[0].ny, 64u);
}

}  // namespace
}  // namespace maille
