// Vertex block descent in SIMD lanes (src/integrators/vbd_lanes.hpp) against the scalar sweep:
// the same bits at every width this CPU runs (2, 4 and 8 lanes; a width the CPU lacks is
// skipped and said), for the kernels alone on a cloth's pools and for whole steps on cloth
// scenes with and without contacts.
#include <gtest/gtest.h>

#include <atomic>
#include <cmath>
#include <cstring>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include "integrators/implicit_system.hpp"
#include "integrators/vbd_lanes.hpp"
#include "maille/builders.hpp"
#include "maille/link_loops.hpp"
#include "maille/scene.hpp"
#include "maille/simulator.hpp"

namespace maille {
namespace {

// A width to test: 2, 4 or 8 lanes in the CPU's instructions, or (portable) 8 lanes in the
// build's own where the CPU has no AVX-512.
struct Width {
  int lanes = 0;
  bool portable = false;
};

// Puts the default width back whatever a test forced.
struct ForcedWidth {
  explicit ForcedWidth(Width w) {
    ok = w.portable ? set_vbd_lane_width_portable() : set_vbd_lane_width(w.lanes);
  }
  ~ForcedWidth() { set_vbd_lane_width(0); }
  bool ok = false;
};

std::vector<Width> lane_widths() {
  std::vector<Width> out;
  for (const int w : {2, 4, 8})
    if (vbd_lane_width_runs(w)) {
      out.push_back({w, false});
    } else {
      std::printf("[ skipped  ] %d lanes: this CPU cannot run them%s\n", w,
                  w == 8 ? " (8 lanes in the build's own instructions instead)" : "");
      if (w == 8) out.push_back({8, true});
    }
  return out;
}

template <class T>
bool same_bits(const std::vector<T>& a, const std::vector<T>& b) {
  return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(T)) == 0;
}

// Links of one pool by point, as VBD keeps them (every link at both ends, in slot order).
struct Csr {
  std::vector<std::uint32_t> row, slots;
};
Csr rows_of(const LinkPoolBase& pool, std::size_t n) {
  Csr r;
  r.row.assign(n + 1, 0);
  const auto ends = pool.slot_ends();
  for (const LinkEnds& e : ends) ++r.row[e.a + 1], ++r.row[e.b + 1];
  for (std::size_t i = 0; i < n; ++i) r.row[i + 1] += r.row[i];
  std::vector<std::uint32_t> at(r.row.begin(), r.row.end() - 1);
  r.slots.resize(r.row[n]);
  for (std::uint32_t l = 0; l < ends.size(); ++l) {
    r.slots[at[ends[l].a]++] = l;
    r.slots[at[ends[l].b]++] = l;
  }
  return r;
}

// The kernels alone: g, H and H^-1 g of every point of a 13 x 11 cloth (structural, shear and
// bending spring-dampers in one pool) at random positions and velocities, with the corner
// cases of the law and of the sums: a point with no link, a zero-length link (two points at
// one place), compressed and stretched links, zero damping, and a -0.0 in g before the pool's
// sum (a point without links must keep it).
TEST(VbdLanes, KernelsGiveTheScalarTermsBitForBit) {
  Model m;
  FlagParams p;
  p.nx = 13;
  p.ny = 11;
  p.mass = 0.3;
  p.material = {400, 0.02};
  p.shear_stiffness = 120;
  p.bending_stiffness = 2;
  build_flag(m, p, "cloth");
  m.points.add(PointKind::free, 0.01, Vec3{5, 5, 5});  // a point of no link
  m.prepare();
  const std::size_t n = m.points.size();
  ASSERT_EQ(m.links.pools().size(), 1u);
  const LinkPoolBase& pool = *m.links.pools()[0];
  ASSERT_TRUE(VbdLanes::runs(pool));
  const Csr csr = rows_of(pool, n);

  std::mt19937 rng(7);
  std::uniform_real_distribution<double> jitter(-0.02, 0.02), speed(-1, 1);
  std::vector<Vec3> x(n), v(n), y(n);
  for (std::size_t i = 0; i < n; ++i) {
    x[i] = m.points.initial_position[i] + Vec3{jitter(rng), jitter(rng), jitter(rng)};
    v[i] = Vec3{speed(rng), speed(rng), speed(rng)};
    y[i] = x[i] + v[i] * (1.0 / 60);
  }
  x[1] = x[0];                        // a zero-length link
  x[5] = x[4] + (x[5] - x[4]) * 0.5;  // compressed
  v[7] = v[8];                        // no relative velocity
  x[n - 1] = Vec3{0.0, 0.0, 0.0};     // g.x = (-0 - 0) m / h^2 - 0 = -0.0 at the lone point
  y[n - 1] = Vec3{-0.0, 0.0, 0.0};
  v[n - 1] = Vec3{};
  const Real h = Real(1) / 60, inv_h = 1 / h, inv_h2 = inv_h * inv_h, drag = Real(0.3);

  std::vector<std::uint32_t> points(n);
  for (std::uint32_t i = 0; i < n; ++i) points[i] = i;
  // The scalar reference: inertia and drag, the pool's terms, the 3x3 solve.
  std::vector<Vec3> g(n), dx(n);
  std::vector<Mat3> hess(n);
  for (std::size_t i = 0; i < n; ++i) {
    const Real mass = m.points.mass[i];
    g[i] = (y[i] - x[i]) * (mass * inv_h2) - v[i] * (drag * mass);
    hess[i] = Mat3::identity() * (mass * (inv_h2 + drag * inv_h));
  }
  add_point_terms(pool, points, csr.row.data(), csr.slots.data(), x.data(), v.data(), inv_h,
                  g.data(), hess.data());
  for (std::size_t i = 0; i < n; ++i) dx[i] = inverse_spd(hess[i]) * g[i];
  ASSERT_TRUE(std::signbit(g[n - 1].x));

  // Two colours of uneven sizes (partial blocks at both ends), in chunks of 64 as VBD runs them.
  const std::uint32_t split = 70;
  const std::vector<std::uint32_t> colour_row{0, split, std::uint32_t(n)};
  const LanePoolRows rows{&pool, csr.row.data(), csr.slots.data()};
  for (const Width w : lane_widths()) {
    ForcedWidth forced(w);
    ASSERT_TRUE(forced.ok);
    VbdLanes lanes;
    lanes.arrange({&rows, 1}, colour_row, points);
    ASSERT_EQ(lanes.width(), w.lanes);
    std::vector<Vec3> g2(n), dx2(n);
    std::vector<Mat3> hess2(n);
    const vbd_lanes::Step step{&x[0].x, &v[0].x,       &y[0].x, m.points.mass.data(),
                               inv_h,   inv_h * inv_h, drag};
    for (std::uint32_t c = 0; c < 2; ++c)
      for (std::uint32_t off = 0; colour_row[c] + off < colour_row[c + 1]; off += 64) {
        const std::uint32_t count =
            std::min<std::uint32_t>(64, colour_row[c + 1] - colour_row[c] - off);
        lanes.terms(c, off, count, step, &g2[0].x, &hess2[0].m[0][0]);
        lanes.solve(c, off, count, &g2[0].x, &hess2[0].m[0][0], &dx2[colour_row[c] + off].x);
      }
    EXPECT_TRUE(same_bits(g, g2)) << w.lanes << " lanes: g";
    EXPECT_TRUE(same_bits(hess, hess2)) << w.lanes << " lanes: H";
    EXPECT_TRUE(same_bits(dx, dx2)) << w.lanes << " lanes: H^-1 g";
  }
}

// A width the CPU cannot run is refused and changes nothing; 1 (the scalar sweep) always runs.
TEST(VbdLanes, WidthsTheCpuLacksAreRefused) {
  EXPECT_TRUE(vbd_lane_width_runs(1));
  EXPECT_FALSE(set_vbd_lane_width(3));
  EXPECT_FALSE(set_vbd_lane_width(16));
  const int before = vbd_lane_width();
  for (const int w : {2, 4, 8})
    if (!vbd_lane_width_runs(w)) {
      EXPECT_FALSE(set_vbd_lane_width(w));
      EXPECT_EQ(vbd_lane_width(), before);
    }
}

struct Trajectory {
  std::vector<Vec3> x, v;
};

Trajectory run(const std::string& example, std::vector<std::string> overrides, int steps,
               int threads) {
  overrides.insert(overrides.begin(),
                   {"simulation.integrator=implicit_euler", "simulation.implicit.solver=vbd",
                    "simulation.step=0.016666666666666666"});
  auto scene =
      load_scene(std::string(MAILLE_SOURCE_DIR "/examples/") + example + ".toml", overrides);
  EXPECT_TRUE(scene.ok()) << scene.error().to_string();
  scene->settings.backend = "cpu";
  scene->settings.threads = threads;
  Simulator sim(std::move(scene->model), scene->settings);
  EXPECT_TRUE(sim.run_steps(std::uint64_t(steps))) << example;
  return {{sim.state().x().begin(), sim.state().x().end()},
          {sim.state().v().begin(), sim.state().v().end()}};
}

// Whole steps: the scalar sweep's trajectory, bit for bit, at every width. Without contacts
// (a flag in the wind), with a geometric sphere and ground (point contacts) and point-triangle
// self-collision, with point-point self-collision (transient contact links), with [[contact]]
// links (conditional pools after the lanes'), and on two threads over a colour's chunks.
TEST(VbdLanes, StepsGiveTheScalarSweepsBits) {
  struct Case {
    const char* example;
    std::vector<std::string> overrides;
    int steps, threads;
  };
  const std::vector<Case> cases{
      {"flag_in_wind", {"flag[0].resolution=[12,10]"}, 20, 1},
      {"cloth_on_sphere", {"flag[0].resolution=[16,16]"}, 40, 1},
      {"cloth_heap", {}, 30, 1},
      {"lattice_balls_collide", {}, 30, 1},
      {"cloth_on_sphere", {"flag[0].resolution=[48,48]"}, 25, 2},
  };
  for (const Case& c : cases) {
    Trajectory scalar;
    {
      ForcedWidth forced({1, false});
      scalar = run(c.example, c.overrides, c.steps, c.threads);
    }
    for (const Width w : lane_widths()) {
      ForcedWidth forced(w);
      ASSERT_TRUE(forced.ok);
      const Trajectory lanes = run(c.example, c.overrides, c.steps, c.threads);
      EXPECT_TRUE(same_bits(scalar.x, lanes.x) && same_bits(scalar.v, lanes.v))
          << c.example << " on " << c.threads << " threads, " << w.lanes << " lanes"
          << (w.portable ? " (portable)" : "");
    }
  }
}

// set_vbd_lane_kernels (the benchmark of Highway's dispatch, bench/bench_vbd_dispatch_hwy.cpp):
// the sweeps call the kernels given, at their width, and give the table's bits; null puts the
// table back.
const vbd_lanes::Kernels* g_wrapped = nullptr;
std::atomic<long> g_calls{0};
void counted_terms(const vbd_lanes::Block& b, const vbd_lanes::Rows& rows, const vbd_lanes::Step& s,
                   Real* g, Real* h) {
  g_calls.fetch_add(1, std::memory_order_relaxed);
  g_wrapped->terms(b, rows, s, g, h);
}
void counted_solve(const std::uint32_t* points, std::uint32_t lanes, const Real* g, const Real* h,
                   Real* out) {
  g_calls.fetch_add(1, std::memory_order_relaxed);
  g_wrapped->solve(points, lanes, g, h, out);
}

TEST(VbdLanes, KernelsGivenByHandRunInsteadOfTheTable) {
  if (!vbd_lane_width_runs(2)) GTEST_SKIP() << "no lanes in this build";
  const int before = vbd_lane_width();
  Trajectory table;
  {
    ForcedWidth forced({2, false});
    g_wrapped = vbd_lane_kernels();
    table = run("cloth_on_sphere", {"flag[0].resolution=[16,16]"}, 20, 1);
  }
  ASSERT_NE(g_wrapped, nullptr);
  const vbd_lanes::Kernels counting{2, &counted_terms, &counted_solve};
  set_vbd_lane_kernels(&counting);
  EXPECT_EQ(vbd_lane_width(), 2);
  g_calls = 0;
  const Trajectory given = run("cloth_on_sphere", {"flag[0].resolution=[16,16]"}, 20, 1);
  set_vbd_lane_kernels(nullptr);
  EXPECT_GT(g_calls.load(), 0);
  EXPECT_TRUE(same_bits(table.x, given.x) && same_bits(table.v, given.v));
  EXPECT_EQ(vbd_lane_width(), before);
}

}  // namespace
}  // namespace maille
