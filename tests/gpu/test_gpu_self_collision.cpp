// The GPU's self-collision (src/gpu/gpu_self_collision.*) against the CPU stage: the contact
// forces on the same input with each exclusion and with and without friction, the counting
// sort and the pairs it finds, and a whole run within the float-storage drift.
//
// Tolerances. The GPU stores x and v in float and computes in float (eps = 2^-24). For one
// contact (a, b) at distance d < s, the normal law k (d - s) n + z (dv . n) n is the conditional
// link's, so its error is bounded as in test_gpu_backend.cpp, plus the rounding of the
// direction: n = d / |d| is off by (2 eps X + 8 eps d) / d, which matters for nearly coincident
// particles (the magnitude m = k (d - s) + z dv . n is then about k s):
//   e_n = 4 eps (k (2 X + 8 (d + s)) + z (2 V + 8 |dv|) + |m| (2 X + 8 d) / d)
// (X, V: the largest coordinate and speed).
// Friction is mu |F_n . n| v_t / max(|v_t|, slip): off by mu e_n through F_n, and by
// mu |F_n| 2 dv_t / max(|v_t|, slip) through the direction, where the tangential velocity's
// error dv_t <= 2 eps V + 8 eps |dv| + |dv| (2 eps X + 8 eps d) / d (the rounding of dv, and of
// n = d / |d| applied to dv); a factor 4 on the whole as for the normal law. The GPU's contact
// forces are read as f(with the stage) - f(without it), which adds the rounding of that
// difference: 4 eps (|f_with| + |f_without|).
// Which pairs touch: a pair within 8 eps (X + s) of s may be decided either way by float
// rounding (where the law's damping jumps); such pairs are counted, their ends left out of the
// force comparison, and the contact counts may differ by them (one per dense cloud here).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <random>

#include "gpu/gpu_test_support.hpp"
#include "intersections.hpp"
#include "maille/backend.hpp"
#include "maille/builders.hpp"
#include "maille/gpu.hpp"
#include "maille/links/spring.hpp"
#include "maille/scene.hpp"
#include "maille/self_collision.hpp"
#include "maille/simulator.hpp"

namespace maille {
namespace {

constexpr double kEps = test::kFloatEps;
using GpuSelfCollision = test::GpuTest;
using test::max_abs;
using test::max_norm;

struct GpuResult {
  std::vector<Vec3> with, without;  // f with the stage and without it
  gpu::SelfCollisionDebug debug;
};

// The GPU's forces at state s, with the stage and without it, and the grid it left.
GpuResult gpu_run(const Model& prepared, const State& s, const Stage& stage) {
  auto b = BackendRegistry::global().find("gpu")->make(BackendOptions{});
  GpuResult r;
  State out(s.size());
  b->load(prepared, s);
  b->evaluate(prepared, s.time);
  b->download(out);
  r.without.assign(out.f().begin(), out.f().end());
  const Stage* stages[] = {&stage};
  b->load(prepared, s, stages);
  b->evaluate(prepared, s.time);
  b->download(out);
  r.with.assign(out.f().begin(), out.f().end());
  auto d = gpu::self_collision_debug(*b);
  EXPECT_TRUE(d.has_value());
  if (d) r.debug = std::move(*d);
  return r;
}

struct Expectation {
  std::vector<Vec3> force;            // the CPU stage's contact forces
  std::vector<double> bound;          // per point (header)
  std::vector<std::uint32_t> count;   // contacts per point (both ends)
  std::vector<std::uint8_t> unclear;  // ends of pairs float may decide either way
  std::size_t unclear_pairs = 0;
};

// The CPU stage's contacts at (x, v), their bounds, and the pairs near the threshold.
Expectation cpu_expectation(const Model& m, const SelfCollisionSettings& settings, const State& s) {
  SelfCollisionEngine engine(m, settings);
  const SelfCollisionSettings& st = engine.settings();  // radius resolved
  const auto x = s.x(), v = s.v();
  Expectation e;
  e.force.assign(s.size(), Vec3{});
  engine.apply(x.data(), v.data(), e.force.data(), 1);
  e.bound.assign(s.size(), 0);
  e.count.assign(s.size(), 0);
  e.unclear.assign(s.size(), 0);
  const double X = max_abs(x), V = max_norm(v), r = st.radius, k = st.stiffness, z = st.damping,
               mu = st.friction, slip = kSelfCollisionSlip;
  for (auto [a, b] : engine.close_pairs(x.data(), 1)) {
    ++e.count[a], ++e.count[b];
    const Vec3 dvec = x[b] - x[a], dv = v[b] - v[a];
    const double d = norm(dvec), w = norm(dv);
    const Vec3 n = dvec / Real(d);
    const double fn = std::abs(k * (d - r) + z * dot(dv, n));
    const Vec3 vt = dv - n * dot(dv, n);
    const double en =
        4 * kEps * (k * (2 * X + 8 * (d + r)) + z * (2 * V + 8 * w) + fn * (2 * X + 8 * d) / d);
    const double dvt = 2 * kEps * V + 8 * kEps * w + w * (2 * kEps * X + 8 * kEps * d) / d;
    const double ef = mu * (en + 4 * fn * 2 * dvt / std::max(double(norm(vt)), slip));
    e.bound[a] += en + ef;
    e.bound[b] += en + ef;
  }
  // Pairs within the band of the threshold, close or not, excluded or not (brute force).
  const double band = 8 * kEps * (X + r);
  std::vector<std::uint8_t> in(s.size(), 0);
  for (const Group& g : m.groups)
    if (settings.groups.empty() ||
        std::find(settings.groups.begin(), settings.groups.end(), g.name) != settings.groups.end())
      for (std::uint32_t p = g.first; p < g.first + g.count; ++p) in[p] = m.points.inv_mass[p] > 0;
  for (std::uint32_t a = 0; a < s.size(); ++a)
    for (std::uint32_t b = a + 1; in[a] && b < s.size(); ++b)
      if (in[b] && std::abs(double(norm(x[b] - x[a])) - r) < band)
        e.unclear[a] = e.unclear[b] = 1, ++e.unclear_pairs;
  return e;
}

// GPU contact forces (with - without) against the CPU's, point by point; contact counts equal
// where no pair is unclear. Returns the worst error over its bound.
double expect_contacts_match(const Model& m, const SelfCollisionSettings& settings, const State& s,
                             const char* what) {
  Model prepared = m;
  prepared.prepare();
  const Expectation e = cpu_expectation(prepared, settings, s);
  const auto stage = make_self_collision_stage(prepared, settings);
  const GpuResult g = gpu_run(prepared, s, *stage);
  std::size_t contacts = 0, compared = 0;
  double worst = 0;
  for (std::uint32_t i = 0; i < s.size(); ++i) {
    contacts += e.count[i];
    if (e.unclear[i]) continue;
    ++compared;
    const Vec3 got = g.with[i] - g.without[i];
    const double allowed = e.bound[i] + 4 * kEps * (norm(g.with[i]) + norm(g.without[i])) + 1e-30;
    const double err = norm(got - e.force[i]);
    EXPECT_LE(err, allowed) << what << ": point " << i << ", " << e.count[i] << " contacts";
    worst = std::max(worst, err / allowed);
  }
  // Contacts per particle: the GPU's pair set is the CPU's.
  const auto& d = g.debug;
  std::size_t gpu_contacts = 0, unclear_ends = 0;
  for (std::size_t a = 0; a < d.particles.size(); ++a) {
    const std::uint32_t p = d.particles[a];
    gpu_contacts += d.contacts[a];
    unclear_ends += e.unclear[p];
    if (!e.unclear[p]) {
      EXPECT_EQ(d.contacts[a], e.count[p]) << what << ": point " << p;
    }
  }
  if (e.unclear_pairs == 0) {
    EXPECT_EQ(gpu_contacts, contacts) << what;
  }
  std::printf(
      "%s: %zu contacts, %zu unclear pairs, %zu points compared, worst error %.3g of "
      "its bound\n",
      what, contacts / 2, e.unclear_pairs, compared, worst);
  EXPECT_LE(unclear_ends, 2 * e.unclear_pairs);
  EXPECT_GT(contacts, 0u) << what;
  return worst;
}

// A 24 x 24 cloth folded in an accordion (layers 0.6 spacings apart), shaken: many contacts
// between layers, and close topological neighbours that the exclusion must remove.
State crumpled(Model& m, std::uint32_t seed) {
  CrumpledClothParams p;
  p.n = 24;
  build_crumpled_cloth(m, p, "cloth");
  m.fields.gravity = {Real(0.5), Real(-9.81), 0};
  State s(m.points.size());
  std::mt19937 rng(seed);
  std::normal_distribution<Real> g(0, 1);
  for (std::size_t i = 0; i < s.size(); ++i) {
    s.x()[i] = m.points.initial_position[i] + Vec3{g(rng), g(rng), g(rng)} * Real(0.002);
    s.v()[i] = Vec3{g(rng), g(rng), g(rng)} * Real(0.5);
  }
  return s;
}

TEST_F(GpuSelfCollision, ContactForcesMatchTheCpuStageOnACrumpledCloth) {
  for (Exclusion ex : {Exclusion::none, Exclusion::matrix, Exclusion::signature})
    for (Real mu : {Real(0), Real(0.3)}) {
      Model m;
      const State s = crumpled(m, 11);
      SelfCollisionSettings settings;
      settings.radius = Real(0.03);  // the spacing is 0.043 m, the layers 0.026 m apart
      settings.stiffness = 400;
      settings.damping = Real(0.3);
      settings.friction = mu;
      settings.exclusion = ex;
      const std::string what = "cloth, exclusion " + std::string(to_string(ex)) +
                               (mu > 0 ? ", friction" : ", no friction");
      expect_contacts_match(m, settings, s, what.c_str());
    }
}

// A random walk folded into a 0.25 m box (steps of 3 cm, contact distance 5 cm): dense, with
// chain neighbours that are close in space (excluded within R = 2 as matrix rows: not a grid).
State walk(Model& m, std::size_t n, std::uint32_t seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<Real> g(0, 1);
  Vec3 p{1, 2, -1};
  for (std::size_t i = 0; i < n; ++i) {
    m.points.add(PointKind::free, Real(0.01), p, Vec3{g(rng), g(rng), g(rng)});
    Vec3 step{g(rng), g(rng), g(rng)};
    p += step * (Real(0.03) / norm(step));
    for (Real* c : {&p.x, &p.y, &p.z}) {
      const Real centre = c == &p.x ? 1 : c == &p.y ? 2 : -1;
      if (std::abs(*c - centre) > Real(0.125)) *c = 2 * centre - *c;  // reflect back in
    }
    if (i > 0) m.links.pool<Spring>().add({std::uint32_t(i - 1), std::uint32_t(i)}, {50, 0.03});
  }
  m.groups.push_back({"walk", "points", 0, std::uint32_t(n)});
  m.fields.gravity = {};
  State s(n);
  for (std::size_t i = 0; i < n; ++i) {
    s.x()[i] = m.points.initial_position[i];
    s.v()[i] = m.points.initial_velocity[i];
  }
  return s;
}

TEST_F(GpuSelfCollision, ContactForcesMatchTheCpuStageInADenseCloud) {
  for (Exclusion ex : {Exclusion::none, Exclusion::matrix})
    for (Real mu : {Real(0), Real(0.5)}) {
      Model m;
      const State s = walk(m, 2000, 5);
      SelfCollisionSettings settings;
      settings.radius = Real(0.05);
      settings.stiffness = 800;
      settings.damping = Real(0.5);
      settings.friction = mu;
      settings.exclusion = ex;
      const std::string what = "cloud, exclusion " + std::string(to_string(ex)) +
                               (mu > 0 ? ", friction" : ", no friction");
      expect_contacts_match(m, settings, s, what.c_str());
    }
}

// The counting sort: `order` is a permutation sorted by cell then index, cell_start its exclusive
// prefix sums (last = n), each particle inside its cell (border cells take what is outside), the
// grid within its budget and its cells no smaller than s. Uses a sparse cloud of 40000 particles
// (a 320000-cell budget: a scan of three levels) and the dense one (two levels).
void expect_counting_sort(const gpu::SelfCollisionDebug& d, std::span<const Vec3> x, Real radius) {
  const std::size_t n = d.particles.size();
  ASSERT_EQ(d.order.size(), n);
  ASSERT_EQ(d.cell_start.size(), std::size_t(d.budget) + 1);
  const std::uint64_t cells = std::uint64_t(d.dims[0]) * d.dims[1] * d.dims[2];
  EXPECT_LE(cells, d.budget);
  EXPECT_GE(d.cell, float(radius));
  EXPECT_EQ(d.cell_start.back(), n);
  std::vector<std::uint32_t> per_cell(d.budget, 0);
  for (std::uint32_t c : d.cell_of) {
    ASSERT_LT(c, cells);
    ++per_cell[c];
  }
  std::vector<std::uint8_t> seen(n, 0);
  for (std::uint32_t c = 0; c < d.budget; ++c) {
    ASSERT_EQ(d.cell_start[c + 1] - d.cell_start[c], per_cell[c]) << "cell " << c;
    for (std::uint32_t k = d.cell_start[c]; k < d.cell_start[c + 1]; ++k) {
      const std::uint32_t a = d.order[k];
      ASSERT_LT(a, n);
      EXPECT_FALSE(seen[a]);
      seen[a] = 1;
      EXPECT_EQ(d.cell_of[a], c);
      if (k > d.cell_start[c]) {
        EXPECT_LT(d.order[k - 1], a) << "cell " << c;
      }
    }
  }
  // Each particle within its cell's box, to float rounding of the cell coordinates.
  const double tol = 1e-5;
  for (std::size_t a = 0; a < n; ++a) {
    const std::uint32_t c = d.cell_of[a];
    const std::uint32_t idx[3] = {c % d.dims[0], (c / d.dims[0]) % d.dims[1],
                                  c / (d.dims[0] * d.dims[1])};
    const Vec3 p = x[d.particles[a]];
    const double q[3] = {(p.x - d.origin[0]) / d.cell, (p.y - d.origin[1]) / d.cell,
                         (p.z - d.origin[2]) / d.cell};
    for (int k = 0; k < 3; ++k) {
      EXPECT_GE(q[k], idx[k] - tol) << "particle " << a;
      if (idx[k] + 1 < d.dims[k]) {
        EXPECT_LT(q[k], idx[k] + 1 + tol) << "particle " << a;
      }
    }
  }
}

TEST_F(GpuSelfCollision, CountingSortAndPairsMatchTheCpu) {
  {  // sparse and large: three scan levels
    Model m;
    std::mt19937 rng(3);
    std::uniform_real_distribution<Real> u(0, 4);
    for (int i = 0; i < 40000; ++i)
      m.points.add(PointKind::free, 1, {u(rng) - 2, u(rng), u(rng) - 9}, {});
    m.groups.push_back({"cloud", "points", 0, 40000});
    m.fields.gravity = {};
    State s(m.points.size());
    for (std::size_t i = 0; i < s.size(); ++i) s.x()[i] = m.points.initial_position[i];
    SelfCollisionSettings settings;
    settings.radius = Real(0.02);
    settings.exclusion = Exclusion::none;
    Model prepared = m;
    prepared.prepare();
    const auto stage = make_self_collision_stage(prepared, settings);
    const GpuResult g = gpu_run(prepared, s, *stage);
    expect_counting_sort(g.debug, s.x(), settings.radius);
    // The pairs: per particle as many as the CPU's uniform grid finds (exact, like brute force).
    SelfCollisionEngine engine(prepared, settings);
    std::vector<std::uint32_t> count(s.size(), 0);
    const auto pairs = engine.close_pairs(s.x().data(), 1);
    for (auto [a, b] : pairs) ++count[a], ++count[b];
    std::size_t total = 0;
    for (std::size_t a = 0; a < g.debug.particles.size(); ++a) {
      EXPECT_EQ(g.debug.contacts[a], count[g.debug.particles[a]]) << "particle " << a;
      total += g.debug.contacts[a];
    }
    EXPECT_EQ(total, 2 * pairs.size());
    EXPECT_GT(pairs.size(), 100u);
    std::printf("sparse cloud: %zu pairs, grid %u x %u x %u of %.4g m (budget %u)\n", pairs.size(),
                g.debug.dims[0], g.debug.dims[1], g.debug.dims[2], double(g.debug.cell),
                g.debug.budget);
  }
  {  // dense: two levels; pairs against brute force through the force test's counts
    Model m;
    const State s = walk(m, 2000, 8);
    SelfCollisionSettings settings;
    settings.radius = Real(0.05);
    settings.broad_phase = BroadPhase::brute;
    settings.exclusion = Exclusion::matrix;
    Model prepared = m;
    prepared.prepare();
    const auto stage = make_self_collision_stage(prepared, settings);
    const GpuResult g = gpu_run(prepared, s, *stage);
    expect_counting_sort(g.debug, s.x(), settings.radius);
    expect_contacts_match(m, settings, s, "cloud against brute force");
  }
}

TEST_F(GpuSelfCollision, TrianglesAreRefusedByName) {
  const std::vector<std::string> sets{"self_collision.primitive=triangles"};
  auto scene = load_scene(MAILLE_SOURCE_DIR "/examples/flag_storm.toml", sets);
  ASSERT_TRUE(scene) << scene.error().to_string();
  scene->settings.backend = "gpu";
  try {
    Simulator sim(scene->model, scene->settings);
    FAIL() << "accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("stage 'self_collision' with primitive = \"triangles\""),
              std::string::npos)
        << e.what();
  }
}

// The GPU builds its own uniform grid: another broad phase is refused by name, in the scene and
// as a live option (set back, the step goes on with the option the device honours).
TEST_F(GpuSelfCollision, BroadPhasesOtherThanUniformAreRefusedNeverIgnored) {
  const std::vector<std::string> sets{"self_collision.broad_phase=hashed"};
  auto scene = load_scene(MAILLE_SOURCE_DIR "/examples/flag_storm.toml", sets);
  ASSERT_TRUE(scene) << scene.error().to_string();
  scene->settings.backend = "gpu";
  try {
    Simulator sim(scene->model, scene->settings);
    FAIL() << "accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("broad_phase = \"hashed\" has no GPU version"),
              std::string::npos)
        << e.what();
  }
  auto uniform = load_scene(MAILLE_SOURCE_DIR "/examples/flag_storm.toml");
  ASSERT_TRUE(uniform) << uniform.error().to_string();
  uniform->settings.backend = "gpu";
  Simulator sim(uniform->model, uniform->settings);
  EXPECT_THROW(sim.set_stage_option("self_collision", "broad_phase", "brute"),
               std::invalid_argument);
  std::string now;
  for (const auto& st : sim.stage_options())
    for (const auto& o : st.options)
      if (st.stage == "self_collision" && o.name == "broad_phase") now = o.value;
  EXPECT_EQ(now, "uniform");
  EXPECT_TRUE(sim.run_steps(2));
}

// A whole run: the cloth heap from a state with contacts (0.4 s into the CPU run), 120 steps on
// the CPU, on the CPU with x and v rounded to float every step, and on the GPU; the GPU stays
// within 4 times the float-storage drift (test_gpu_runs.cpp), and its cloth crosses itself no
// more than the CPU's does.
TEST_F(GpuSelfCollision, ClothHeapStaysWithinTheFloatStorageDriftOfTheCpu) {
  // The heap on its former floor of fixed points and conditional links (the example's floor is
  // now a plane obstacle, a stage the GPU lacks).
  auto loaded = load_scene(MAILLE_SOURCE_DIR "/tests/data/cloth_heap_links.toml");
  ASSERT_TRUE(loaded) << loaded.error().to_string();
  const Scene& scene = *loaded;
  SimulationSettings settings = scene.settings;
  settings.threads = 1;
  Simulator start(scene.model, settings);
  start.run_steps(2000);
  const State from = start.state();
  const std::uint64_t steps = 120;  // 0.1 s per step on llvmpipe: the floor's 257k contacts
  std::uint64_t contacts = 0;
  auto run = [&](const std::string& backend, bool float_storage) {
    SimulationSettings st = settings;
    st.backend = backend;
    Simulator sim(scene.model, st);
    sim.restore(from);
    for (std::uint64_t k = 0; k < steps; ++k) {
      EXPECT_TRUE(sim.step()) << backend << " step " << k;
      if (float_storage) test::round_to_float(sim.state_for_editing());
      if (backend == "cpu" && !float_storage)
        for (const auto& c : sim.profile().counters())
          if (c.name == "self_contacts") contacts += c.last;
    }
    EXPECT_TRUE(sim.check_energy());
    return std::vector<Vec3>(sim.state().x().begin(), sim.state().x().end());
  };
  const auto cpu = run("cpu", false), rounded = run("cpu", true), gpu = run("gpu", false);
  const double drift = test::max_distance(cpu, rounded), off = test::max_distance(cpu, gpu);
  std::printf(
      "cloth_heap, %llu steps from t = 0.4 s (%.1f contacts per step on the CPU): GPU - "
      "CPU %.3g m, float-storage drift %.3g m (ratio %.2f)\n",
      static_cast<unsigned long long>(steps), double(contacts) / double(steps), off, drift,
      off / drift);
  EXPECT_GT(contacts, 10 * steps);
  EXPECT_GT(drift, 0.0);
  EXPECT_LE(off, 4 * drift + 1e-6);
  // The cloth's triangles (the group's faces) do not cross each other more on the GPU.
  const Group* cloth = scene.model.group("cloth");
  ASSERT_NE(cloth, nullptr);
  std::vector<std::array<std::uint32_t, 3>> tris;
  for (const auto& t : scene.model.surface.triangles)
    if (t[0] >= cloth->first && t[0] < cloth->first + cloth->count) tris.push_back(t);
  const std::size_t on_cpu = test::count_self_intersections(cpu, tris),
                    on_gpu = test::count_self_intersections(gpu, tris);
  std::printf("crossing triangle pairs: CPU %zu, GPU %zu\n", on_cpu, on_gpu);
  EXPECT_LE(on_gpu, on_cpu);
}

}  // namespace
}  // namespace maille
