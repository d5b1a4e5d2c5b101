// The lean audio-rate step (docs/sound.md, "A lean step"): stage timings only on sampled steps,
// health checks at a cadence, no finiteness pass before read-only stages. None of it changes a
// bit of the motion; what it drops is bookkeeping. And the square drum the period budget is
// measured on (a net with pretension and fixed edges) rings at its lattice's own frequency.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <numbers>

#include "maille/live.hpp"
#include "maille/scene.hpp"
#include "maille/simulator.hpp"
#include "maille/spectrum.hpp"

namespace maille {
namespace {

const std::string kSquare = std::string(MAILLE_SOURCE_DIR) + "/bench/scenes/play_square_drum.toml";
const std::string kString = std::string(MAILLE_SOURCE_DIR) + "/examples/sound_plucked_string.toml";

Scene scene_of(const std::string& path, const std::vector<std::string>& sets = {}) {
  Result<Scene> s = load_scene(path, sets);
  EXPECT_TRUE(s.ok()) << (s.ok() ? "" : s.error().to_string());
  return std::move(s.value());
}

// The same run, ordinary and lean: every position and velocity equal, bit for bit. The plucked
// string has a driven finger, a conditional link and two listeners (one reads forces).
TEST(LeanStep, GivesTheSameBitsAsTheOrdinaryStep) {
  Scene a = scene_of(kString), b = scene_of(kString);
  a.settings.threads = b.settings.threads = 1;
  Simulator plain(a.model, a.settings), lean(b.model, b.settings);
  audio::Recorder ra(a.audio, a.settings.step), rb(b.audio, b.settings.step);
  ra.attach(plain);
  rb.attach(lean);
  lean.set_stage_timing(Simulator::StageTiming::sampled_steps);
  lean.set_health_every(64);
  ASSERT_TRUE(plain.run_steps(5000));
  ASSERT_TRUE(lean.run_steps(5000));
  const State &p = plain.state(), &l = lean.state();
  for (std::size_t i = 0; i < p.size(); ++i) {
    ASSERT_EQ(p.x()[i].x, l.x()[i].x) << i;
    ASSERT_EQ(p.x()[i].y, l.x()[i].y) << i;
    ASSERT_EQ(p.v()[i].y, l.v()[i].y) << i;
  }
  ra.finish();
  rb.finish();
  EXPECT_EQ(ra.channels(), rb.channels());
}

double timed_ns(const Profile& p) {
  double t = 0;
  for (const auto& s : p.stages()) t += s.last_ns;
  return t;
}

// With sampled-step timing a sampled step is timed completely (stats.csv's row) and the others
// read no clock (their last_ns stay 0).
TEST(LeanStep, TimesTheSampledStepsOnly) {
  Scene s = scene_of(kString);
  s.settings.threads = 1;
  s.settings.sample_every = 10;
  Simulator sim(s.model, s.settings);
  sim.set_stage_timing(Simulator::StageTiming::sampled_steps);
  int timed_rows = 0;
  sim.on_sample([&](const EnergySample&, const Profile& p) { timed_rows += timed_ns(p) > 0; });
  for (int k = 0; k < 40; ++k) {
    const bool sampled = sim.steps_taken() % 10 == 0;
    ASSERT_TRUE(sim.step());
    if (sampled)
      EXPECT_GT(timed_ns(sim.profile()), 0) << "step " << k;
    else
      EXPECT_EQ(timed_ns(sim.profile()), 0) << "step " << k;
  }
  EXPECT_EQ(timed_rows, 4);
}

// A non-finite position that no force reads (a free point alone, no drag) is found by the health
// check only: at its step when checked every step, at the next multiple of n when every n.
TEST(LeanStep, HealthAtACadenceFindsAPoisonedPointWithinItsSteps) {
  for (const int every : {1, 16}) {
    Model m;
    m.fields.gravity = {0, -9.81, 0};
    m.fields.air_drag = 0;
    m.points.add(PointKind::free, 1, {0, 0, 0});
    m.points.add(PointKind::free, 1, {1, 0, 0});
    SimulationSettings st;
    st.step = 1e-3;
    st.threads = 1;
    st.publish_every = st.sample_every = kNeverEvery;  // no energy sample to find it first
    Simulator sim(std::move(m), st);
    sim.set_health_every(every);
    ASSERT_TRUE(sim.run_steps(5));
    sim.state_for_editing().x()[1].x = std::numeric_limits<Real>::quiet_NaN();
    std::uint64_t steps = 0;
    while (sim.step()) ASSERT_LT(++steps, 100u);
    ASSERT_TRUE(sim.blow_up().has_value());
    // The check runs at the end of a step, on the step count after it.
    EXPECT_EQ(sim.blow_up()->step, every == 1 ? 6u : 16u) << "every " << every;
  }
}

// The square drum: n x n beads of mass m, edges fixed, links of stiffness k under pretension p
// (tension k p a, transverse stiffness k p per link). The lattice's (1,1) mode with N = n - 2
// free beads per side: omega^2 = (8 k p / m) sin^2(pi / (2 (N + 1))). Struck at the centre,
// heard near it, 12 x 12 beads: 266.5 Hz; the leapfrog step at 48 kHz shifts it by
// (omega h)^2 / 24 = 5e-5, the spectrum's interpolation by less than 0.05 % at 2 s; a strike of
// 0.3 m/s keeps the tension's own modulation (amplitude / spacing, squared) below 1e-4.
TEST(LeanStep, SquareDrumRingsAtItsLatticeMode) {
  const int n = 12;
  const double a = 0.3 / 13, bead = 0.05 / 523;
  const std::vector<std::string> sets{"net[0].resolution=[12,12]",
                                      "net[0].width=" + std::to_string(a * (n - 1)),
                                      "net[0].depth=" + std::to_string(a * (n - 1)),
                                      "net[0].mass=" + std::to_string(bead * n * n),
                                      "listen[0].point=skin:78",  // (6, 6): beside the centre
                                      "control[0].excite.point=skin:65"};
  Scene s = scene_of(kSquare, sets);
  SimulationSettings st = s.settings;
  st.threads = 1;
  st.publish_every = st.sample_every = kNeverEvery;
  Simulator sim(s.model, st);
  audio::LiveSource src(sim, s.audio, 48000, {}, 64);
  ASSERT_TRUE(src.plan().exact);
  src.control({0, 1.0f, 0.1f});  // 0.3 m/s: small enough to stay linear
  std::vector<float> out(96000);
  src.render(out.data(), out.size());
  ASSERT_FALSE(src.blown_up());
  const double k = 16550, p = 0.1, m = s.model.points.mass[78];
  const double expected = std::sqrt(8 * k * p / m) * std::sin(std::numbers::pi / (2 * (n - 1))) /
                          (2 * std::numbers::pi);
  const double f = spectrum::dominant(out, 48000, 100, 400).frequency;
  EXPECT_NEAR(f, expected, 0.002 * expected);
}

}  // namespace
}  // namespace maille
