// The lean audio-rate step (docs/sound.md, "A lean step"): stage timings only on sampled steps,
// health checks at a cadence, no finiteness pass before read-only stages. None of it changes a
// bit of the motion; what it drops is bookkeeping.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "maille/live.hpp"
#include "maille/scene.hpp"
#include "maille/simulator.hpp"

namespace maille {
namespace {

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

}  // namespace
}  // namespace maille
