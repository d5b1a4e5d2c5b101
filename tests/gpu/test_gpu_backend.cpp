// The GPU backend (src/gpu) against the CPU, its oracle: each GPU stage on the same input as the
// CPU stage, then whole runs, the blow-up detection and the refusals. They run on whatever
// OpenGL 4.5 driver EGL finds: Mesa's llvmpipe in CI, a GPU elsewhere.
//
// Tolerances come from float arithmetic. The GPU stores positions and velocities in float
// (relative rounding eps = 2^-24 = 6e-8) and computes in float. For a link, rounding x to float
// moves d = x_b - x_a by at most 2 eps X (X the largest coordinate), and every operation of the
// law adds at most eps relative: the force of a spring is off by at most about
// k (2 eps X + c eps (|d| + L0)) and a damper's by z (2 eps V + c eps |dv|) with c a small count
// of operations. The bounds below take c = 8 and a factor 4 on the whole for the sum over a
// point's links (rounding errors of a sum grow with the number of terms); a GPU compiler may
// fuse multiply-adds, which only removes roundings.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "gpu/gpu_test_support.hpp"
#include "maille/backend.hpp"
#include "maille/builders.hpp"
#include "maille/gpu.hpp"
#include "maille/links/conditional.hpp"
#include "maille/links/damper.hpp"
#include "maille/links/spring.hpp"
#include "maille/links/spring_damper.hpp"
#include "maille/scene.hpp"
#include "maille/simulator.hpp"

namespace maille {
namespace {

constexpr double kEps = test::kFloatEps;
using Gpu = test::GpuTest;

std::unique_ptr<Backend> make_gpu() {
  return BackendRegistry::global().find("gpu")->make(BackendOptions{});
}

// The forces the CPU computes at state s (every force stage: links, fields, wind, drives).
State cpu_forces(const Model& m, const State& s) {
  SimulationSettings settings;
  settings.threads = 1;
  Simulator sim(m, settings);
  sim.restore(s);
  sim.energies();  // runs the force pass at the state
  return sim.state();
}

State gpu_forces(const Model& m, const State& s) {
  Model prepared = m;
  prepared.prepare();
  auto b = make_gpu();
  b->load(prepared, s);
  b->evaluate(prepared, s.time);
  State out(s.size());
  b->download(out);
  return out;
}

// A cloud of points in a 1 m box at up to 5 m from the origin, with random velocities.
State random_state(Model& m, std::size_t n, std::mt19937& rng) {
  std::uniform_real_distribution<Real> u(-1, 1);
  for (std::size_t i = 0; i < n; ++i)
    m.points.add(PointKind::free, Real(0.01) + Real(0.1) * (u(rng) + 1),
                 Vec3{4 + u(rng) * Real(0.5), 1 + u(rng) * Real(0.5), u(rng) * Real(0.5)},
                 Vec3{u(rng), u(rng), u(rng)});
  m.points.set_kind(0, PointKind::fixed);
  State s(n);
  for (std::size_t i = 0; i < n; ++i) {
    s.x()[i] = m.points.initial_position[i];
    s.v()[i] = m.points.initial_velocity[i];
  }
  return s;
}

double max_abs(const State& s) {
  return test::max_abs(s.x());
}
double max_speed(const State& s) {
  return test::max_norm(s.v());
}

// Per point: the bound of the header's derivation, from each link's stiffness and damping.
std::vector<double> link_bounds(const Model& m, const State& s) {
  const double X = max_abs(s), V = max_speed(s);
  std::vector<double> bound(s.size(), 0);
  for (const auto& pool : m.links.pools()) {
    const auto fields = pool->fields();
    for (std::size_t id = 0; id < pool->size(); ++id) {
      double k = 0, z = 0, L = 0;
      for (std::size_t f = 0; f < fields.size(); ++f) {
        const double p = pool->param(id, f);
        if (fields[f].name == "stiffness") k = p;
        if (fields[f].name == "damping") z = p;
        if (fields[f].name == "rest_length" || fields[f].name == "threshold") L = std::max(L, p);
      }
      const auto [a, b] = pool->ends(id);
      const double d = norm(s.x()[b] - s.x()[a]), dv = norm(s.v()[b] - s.v()[a]);
      const double e = 4 * kEps * (k * (2 * X + 8 * (d + L)) + z * (2 * V + 8 * dv));
      bound[a] += e;
      bound[b] += e;
    }
  }
  return bound;
}

// |f_gpu - f_cpu| within bound + the fields' share (m |g| and m gamma |v| to 4 eps), point by
// point; returns the largest error over its bound (reported, < 1 required).
double compare_forces(const Model& m, const State& s, const std::vector<double>& bound) {
  const State cpu = cpu_forces(m, s), gpu = gpu_forces(m, s);
  double worst = 0;
  for (std::size_t i = 0; i < s.size(); ++i) {
    const double fields =
        4 * kEps * m.points.mass[i] * (norm(m.fields.gravity) + m.fields.air_drag * norm(s.v()[i]));
    const double allowed = bound[i] + fields + 1e-30;
    const double err = norm(gpu.f()[i] - cpu.f()[i]);
    EXPECT_LE(err, allowed) << "point " << i << ": gpu " << gpu.f()[i].x << " cpu " << cpu.f()[i].x;
    worst = std::max(worst, err / allowed);
  }
  return worst;
}

template <class Kind>
void random_links(Model& m, std::size_t count, std::mt19937& rng,
                  typename Kind::Params (*params)(std::mt19937&, Real distance)) {
  auto& pool = m.links.pool<Kind>();
  std::uniform_int_distribution<std::uint32_t> pick(0, m.points.size() - 1);
  while (pool.size() < count) {
    const std::uint32_t a = pick(rng), b = pick(rng);
    if (a == b) continue;
    const Real d = norm(m.points.initial_position[b] - m.points.initial_position[a]);
    pool.add({a, b}, params(rng, d));
  }
}

Real uniform(std::mt19937& rng, Real lo, Real hi) {
  return std::uniform_real_distribution<Real>(lo, hi)(rng);
}

TEST_F(Gpu, SpringForcesMatchTheCpuWithinFloatRounding) {
  std::mt19937 rng(1);
  Model m;
  const State s = random_state(m, 400, rng);
  random_links<Spring>(m, 2000, rng, [](std::mt19937& r, Real d) {
    return Spring::Params{uniform(r, 10, 5000), d * uniform(r, 0.5, 1.5)};
  });
  const double worst = compare_forces(m, s, link_bounds(m, s));
  RecordProperty("worst_error_over_bound", std::to_string(worst));
}

TEST_F(Gpu, DamperForcesMatchTheCpuWithinFloatRounding) {
  std::mt19937 rng(2);
  Model m;
  const State s = random_state(m, 400, rng);
  random_links<Damper>(m, 2000, rng,
                       [](std::mt19937& r, Real) { return Damper::Params{uniform(r, 0.01, 5)}; });
  compare_forces(m, s, link_bounds(m, s));
}

TEST_F(Gpu, SpringDamperForcesMatchTheCpuWithinFloatRounding) {
  std::mt19937 rng(3);
  Model m;
  const State s = random_state(m, 400, rng);
  random_links<SpringDamper>(m, 2000, rng, [](std::mt19937& r, Real d) {
    return SpringDamper::Params{uniform(r, 10, 5000), d * uniform(r, 0.5, 1.5), uniform(r, 0, 5)};
  });
  compare_forces(m, s, link_bounds(m, s));
}

// Thresholds are drawn so that about half the links are active. The law's damping jumps at the
// threshold, so pairs within 1e-5 of it (where float rounding can decide either way) are not
// drawn: a set of measure zero in a simulation, a flaky test here.
TEST_F(Gpu, ConditionalForcesMatchTheCpuWithinFloatRounding) {
  std::mt19937 rng(4);
  Model m;
  const State s = random_state(m, 400, rng);
  random_links<ConditionalSpringDamper>(m, 3000, rng, [](std::mt19937& r, Real d) {
    Real s_ = d * uniform(r, 0.5, 1.5);
    if (std::abs(s_ - d) < Real(1e-5)) s_ = d + Real(1e-3);
    return ConditionalSpringDamper::Params{uniform(r, 10, 5000), uniform(r, 0, 2), s_, s_};
  });
  std::size_t active = 0;
  const auto& pool = m.links.pool<ConditionalSpringDamper>();
  for (std::size_t id = 0; id < pool.size(); ++id) {
    const auto [a, b] = pool.ends(id);
    active += norm(s.x()[b] - s.x()[a]) < pool.params(id).threshold;
  }
  EXPECT_GT(active, 1000u);
  EXPECT_LT(active, 2000u);
  compare_forces(m, s, link_bounds(m, s));
}

TEST_F(Gpu, GravityAndDragMatchTheCpu) {
  std::mt19937 rng(5);
  Model m;
  const State s = random_state(m, 1000, rng);
  m.fields.gravity = {Real(0.3), Real(-9.81), Real(1.2)};
  m.fields.air_drag = Real(0.7);
  compare_forces(m, s, std::vector<double>(s.size(), 0.0));
  const State gpu = gpu_forces(m, s);
  EXPECT_EQ(gpu.f()[0], Vec3{}) << "a fixed point feels no field";
}

// The wind on a flag's faces, gusty: the CPU's grid path computes the pressure law in float too.
// Each face's force is off by a few eps relative from the law, and by the gust's sines: their
// arguments (turns, |r| up to about 2 here) are rounded in float, so a sine is off by about
// 2 pi * 4 eps |r|, and the force, quadratic in the air speed, twice that relative. 1e-5 of the
// largest face force per face, times the 6 faces of a point, covers both with a margin of 2.
TEST_F(Gpu, GustyWindOnFacesMatchesTheCpu) {
  Model m;
  FlagParams flag;
  flag.origin = {Real(0.3), Real(1.0), Real(0.2)};
  flag.nx = 24;
  flag.ny = 16;
  build_flag(m, flag, "flag");
  m.links = LinkSet{};  // the faces alone
  m.fields.gravity = {};
  m.fields.wind.velocity = {6, 0, Real(1.5)};
  m.fields.wind.turbulence = Real(0.5);
  State s(m.points.size());
  std::mt19937 rng(6);
  std::uniform_real_distribution<Real> u(-1, 1);
  for (std::size_t i = 0; i < s.size(); ++i) {
    // Crumple it so that faces face the wind at every angle, and give them velocities.
    s.x()[i] = m.points.initial_position[i] + Vec3{u(rng), u(rng), u(rng)} * Real(0.02);
    s.v()[i] = Vec3{u(rng), u(rng), u(rng)} * Real(2);
  }
  s.time = 1.7;  // the gusts' phases are not zero
  const State cpu = cpu_forces(m, s), gpu = gpu_forces(m, s);
  double biggest = 0;
  for (const Vec3& f : cpu.f()) biggest = std::max(biggest, double(norm(f)));
  ASSERT_GT(biggest, 0.0);
  double worst = 0;
  for (std::size_t i = 0; i < s.size(); ++i)
    worst = std::max(worst, double(norm(gpu.f()[i] - cpu.f()[i])));
  EXPECT_LE(worst, 6e-5 * biggest);
  RecordProperty("worst_relative", std::to_string(worst / biggest));
}

// Driven points: their path at t, uploaded, scattered into x and v.
TEST_F(Gpu, DrivenPointsFollowTheirPath) {
  auto scene = load_scene(MAILLE_SOURCE_DIR "/examples/shaken_flag.toml");
  ASSERT_TRUE(scene) << scene.error().to_string();
  Model m = scene->model;
  m.prepare();
  ASSERT_FALSE(m.drives.empty());
  State s(m.points.size());
  for (std::size_t i = 0; i < s.size(); ++i) s.x()[i] = m.points.initial_position[i];
  auto b = make_gpu();
  b->load(m, s);
  b->drive(m, 0.37);
  State out(s.size());
  b->download(out);
  for (const Drive& d : m.drives) {
    EXPECT_LE(norm(out.x()[d.point] - d.path.position(0.37)), 4 * kEps * max_abs(s) + 1e-12);
    EXPECT_LE(norm(out.v()[d.point] - d.path.velocity(0.37)),
              4 * kEps * norm(d.path.velocity(0.37)) + 1e-12);
  }
}

}  // namespace
}  // namespace maille
