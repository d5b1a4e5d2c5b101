// The flag: held on its pole it stays bounded for a long run; in wind it moves; a run is
// bit-for-bit reproducible, whatever the number of threads.
#include <gtest/gtest.h>

#include "maille/builders.hpp"
#include "maille/links/spring_damper.hpp"
#include "test_support.hpp"

namespace maille {
namespace {

Model windy_flag(std::uint32_t nx, std::uint32_t ny) {
  Model m;
  FlagParams p;
  p.nx = nx;
  p.ny = ny;
  build_flag(m, p, "flag");
  m.fields.air_drag = 0.05;
  m.fields.wind.velocity = {7, 0, 1.5};
  m.fields.wind.turbulence = 0.35;
  m.fields.wind.gust_frequency = 0.8;
  return m;
}

// Largest |d - L0| / L0 over the structural links (rest length at most the grid spacing; shear
// and bending links are longer, and bending links legitimately shorten a lot when cloth folds).
double max_strain(const Simulator& sim, double spacing) {
  const auto* pool = sim.model().links.find("spring_damper");
  double worst = 0;
  for (std::size_t l = 0; l < pool->size(); ++l) {
    const auto [a, b] = pool->ends(l);
    const double rest = pool->param(l, 1);
    if (rest > spacing * 1.001) continue;
    worst = std::max(worst, std::abs(norm(sim.state().x()[b] - sim.state().x()[a]) - rest) / rest);
  }
  return worst;
}

// 30 s of gusty wind at half the stability limit: no blow-up, structural links within 20 % of
// their rest length (the cloth is stiff: 200 N/m per link against ~0.1 N of weight per column and
// ~1 N of gusts), no point further than the flag's diagonal from the pole, and energy bounded.
TEST(Flag, HeldFlagStaysBoundedInWind) {
  Model m = windy_flag(20, 14);
  SimulationSettings s = test::settings(1e-3);
  Simulator probe(m, s);
  s.step = 0.5 * probe.stability().max_step;
  Simulator sim(std::move(m), s);
  const auto steps = static_cast<std::uint64_t>(30.0 / s.step);
  double worst_strain = 0, worst_kinetic = 0;
  for (std::uint64_t i = 0; i < steps; i += 1000) {
    ASSERT_TRUE(sim.run_steps(1000)) << sim.blow_up()->message;
    worst_strain = std::max(worst_strain, max_strain(sim, 1.5 / 19));
    worst_kinetic = std::max(worst_kinetic, sim.energies().kinetic);
  }
  EXPECT_LT(worst_strain, 0.2);
  const double reach = std::sqrt(1.5 * 1.5 + 1.0 * 1.0) + 0.01;
  for (const Vec3& x : sim.state().x()) EXPECT_LT(std::hypot(x.x, x.z), reach);
  // Kinetic energy stays below that of the whole flag moving at the peak gust speed.
  EXPECT_LT(worst_kinetic, 0.5 * 0.3 * std::pow(7 * 1.35 + 1.5, 2));
}

// The wind really acts: the flag is blown downwind (its free edge goes to +x) and keeps moving
// (gusts): kinetic energy in the last seconds is far from zero.
TEST(Flag, WindBlowsAndFlutters) {
  Model m = windy_flag(20, 14);
  SimulationSettings s = test::settings(2e-4);
  Simulator sim(std::move(m), s);
  ASSERT_TRUE(sim.run_steps(static_cast<std::uint64_t>(6.0 / s.step)));
  double mean_x = 0;
  for (const Vec3& x : sim.state().x()) mean_x += x.x / double(sim.state().size());
  EXPECT_GT(mean_x, 0.5);  // built in the x-y plane from x = 0 to 1.5
  double min_k = 1e9, max_k = 0;
  for (int i = 0; i < 20; ++i) {
    sim.run_steps(500);
    const double k = sim.energies().kinetic;
    min_k = std::min(min_k, k);
    max_k = std::max(max_k, k);
  }
  EXPECT_GT(min_k, 1e-4);
  EXPECT_GT(max_k, 1.5 * min_k);  // it flutters: kinetic energy varies
}

// Determinism: the same scene twice gives identical states, bit for bit, and so does running it
// on 1 and 2 threads (links run in coloured chunks whose order is fixed, so every point sums its
// forces in the same order).
TEST(Flag, DeterministicAcrossRunsAndThreads) {
  std::uint64_t hashes[3];
  std::vector<std::uint64_t> frames[3];
  const int threads[3] = {1, 1, 2};
  for (int r = 0; r < 3; ++r) {
    SimulationSettings s = test::settings(2e-4);
    s.threads = threads[r];
    s.publish_every = 250;
    Simulator sim(windy_flag(64, 64), s);  // 4096 points: large enough to use the threads
    sim.on_publish([&, r](const Snapshot& snap) {
      State st(snap.positions.size());
      std::copy(snap.positions.begin(), snap.positions.end(), st.x().begin());
      frames[r].push_back(state_hash(st));
    });
    ASSERT_TRUE(sim.run_steps(1500));
    ASSERT_EQ(sim.threads(), threads[r]);
    hashes[r] = state_hash(sim.state());
  }
  EXPECT_EQ(hashes[0], hashes[1]);
  EXPECT_EQ(hashes[0], hashes[2]);
  EXPECT_EQ(frames[0], frames[1]);
  EXPECT_EQ(frames[0], frames[2]);
  EXPECT_EQ(frames[0].size(), 6u);
}

}  // namespace
}  // namespace maille
