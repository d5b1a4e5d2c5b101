// Playing live (live.hpp, `maille play`): the LiveSource hears exactly what `run --audio` hears;
// a parameter control reaches its target through its glide and never makes a non-finite sample,
// however it is thrown about; its key is tabulated from the scene (linear keys in two rows).
// The allocation test (test_allocation.cpp) counts the audio path's allocations.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "maille/links/friction.hpp"
#include "maille/live.hpp"
#include "maille/scene.hpp"
#include "maille/simulator.hpp"
#include "maille/spectrum.hpp"

namespace maille {
namespace {

const std::string kDrum = std::string(MAILLE_SOURCE_DIR) + "/examples/play_drum.toml";
// The drum made small (91 points): the listened and struck points moved inside its rim.
const std::vector<std::string> kSmall{"membrane[0].rings=6", "listen[0].point=skin:45",
                                      "control[0].excite.point=skin:35"};
const std::string kString = std::string(MAILLE_SOURCE_DIR) + "/examples/sound_plucked_string.toml";

Scene scene_of(const std::string& path, const std::vector<std::string>& sets) {
  Result<Scene> s = load_scene(path, sets);
  EXPECT_TRUE(s.ok()) << (s.ok() ? "" : s.error().to_string());
  return std::move(s.value());
}

SimulationSettings live_settings(const Scene& s) {
  SimulationSettings st = s.settings;
  st.threads = 1;
  st.publish_every = kNeverEvery;
  st.sample_every = kNeverEvery;
  return st;
}

// The plucked string (two channels: a velocity and the bridge's force), exact at 48 kHz.
TEST(Live, RendersExactlyWhatTheRecorderHears) {
  const std::vector<std::string> sets{"simulation.step=2.0833333333333333e-05", "audio.rate=48000",
                                      "audio.gain=0.25"};
  Scene a = scene_of(kString, sets), b = scene_of(kString, sets);
  Simulator offline(a.model, live_settings(a));
  audio::Recorder rec(a.audio, a.settings.step);
  rec.attach(offline);
  const std::size_t frames = 4800;
  offline.run_steps(frames);
  rec.finish();

  Simulator live(b.model, live_settings(b));
  audio::LiveSource src(live, b.audio, 48000, {}, 64);
  ASSERT_TRUE(src.plan().exact);
  std::vector<float> out(frames * 2);
  for (std::size_t f = 0; f < frames; f += 64) src.render(out.data() + f * 2, 64);
  for (std::size_t c = 0; c < 2; ++c)
    for (std::size_t f = 0; f < frames; ++f)
      ASSERT_EQ(out[f * 2 + c], static_cast<float>(0.25 * double(rec.channels()[c][f])))
          << "channel " << c << " frame " << f;
}

// A device rate the step does not divide: the LiveSource resamples (windowed sinc) exactly as
// the Recorder does for a WAV at that rate (the string at 1/44100 s, played at 48 kHz).
TEST(Live, ResamplesLikeTheRecorder) {
  const std::vector<std::string> sets{"audio.rate=48000"};
  Scene a = scene_of(kString, sets), b = scene_of(kString, sets);
  Simulator offline(a.model, live_settings(a));
  audio::Recorder rec(a.audio, a.settings.step);
  ASSERT_FALSE(rec.plan().exact);
  rec.attach(offline);
  offline.run_steps(44100 / 10);
  rec.finish();
  Simulator live(b.model, live_settings(b));
  audio::AudioSpec spec = b.audio;
  spec.settings.gain = 1;
  audio::LiveSource src(live, spec, 48000, {}, 64);
  ASSERT_FALSE(src.plan().exact);
  const std::size_t frames = 4096;  // the Recorder's last samples use a truncated kernel
  ASSERT_GT(rec.channels()[0].size(), frames);
  std::vector<float> out(frames * 2);
  for (std::size_t f = 0; f < frames; f += 64) src.render(out.data() + f * 2, 64);
  for (std::size_t c = 0; c < 2; ++c)
    for (std::size_t f = 0; f < frames; ++f)
      ASSERT_EQ(out[f * 2 + c], rec.channels()[c][f]) << "channel " << c << " frame " << f;
}

// The viewer starts its sound wherever the model is, and makes a new source after a reset, a
// new step or a new simulator: a source made after 1000 steps hears, from there, exactly what
// the Recorder heard at those steps; a source destroyed takes its listen stage with it (the
// simulator then steps on, and a second source hears as the first would have).
TEST(Live, StartsMidRunAndLeavesNoStageBehind) {
  const std::vector<std::string> sets{"simulation.step=2.0833333333333333e-05", "audio.rate=48000",
                                      "audio.gain=0.25"};
  Scene a = scene_of(kString, sets), b = scene_of(kString, sets);
  Simulator offline(a.model, live_settings(a));
  audio::Recorder rec(a.audio, a.settings.step);
  rec.attach(offline);
  offline.run_steps(3000);
  rec.finish();
  const auto expected = [&](std::size_t c, std::size_t step) {
    return static_cast<float>(0.25 * double(rec.channels()[c][step]));
  };

  Simulator live(b.model, live_settings(b));
  ASSERT_TRUE(live.run_steps(1000));
  std::vector<float> out(640 * 2);
  {
    audio::LiveSource first(live, b.audio, 48000, {}, 64);
    for (std::size_t f = 0; f < 640; f += 64) first.render(out.data() + f * 2, 64);
    for (std::size_t c = 0; c < 2; ++c)
      for (std::size_t f = 0; f < 640; ++f)
        ASSERT_EQ(out[f * 2 + c], expected(c, 1000 + f)) << "channel " << c << " frame " << f;
  }
  ASSERT_TRUE(live.run_steps(360));  // no source: nothing listens (ASan: nothing dangles)
  audio::LiveSource second(live, b.audio, 48000, {}, 64);
  for (std::size_t f = 0; f < 640; f += 64) second.render(out.data() + f * 2, 64);
  for (std::size_t c = 0; c < 2; ++c)
    for (std::size_t f = 0; f < 640; ++f)
      ASSERT_EQ(out[f * 2 + c], expected(c, 2000 + f)) << "channel " << c << " frame " << f;
}

TEST(Live, LinearKeyIsTabulatedInTwoRowsAndStartsAtTheScenesValue) {
  Scene s = scene_of(kDrum, kSmall);
  const audio::Control& c = s.audio.controls[1];
  ASSERT_EQ(c.key, "membrane[0].stiffness");
  Result<audio::ParameterTable> t = build_parameter_table(kDrum, kSmall, s.model, s.settings, c);
  ASSERT_TRUE(t.ok()) << t.error().to_string();
  EXPECT_EQ(t.value().rows, 2u);
  EXPECT_EQ(t.value().slots.size(), s.model.links.pools()[0]->size());  // every link's k
  EXPECT_NEAR(t.value().initial, (16550.0 - 8000.0) / (33100.0 - 8000.0), 1e-12);
}

// The skin's radius moves its points (and its rest lengths): not a value a playing model can
// change, refused rather than half applied.
TEST(Live, KeyThatMovesThePointsIsRefusedWithItsLine) {
  Scene s = scene_of(kDrum, kSmall);
  audio::Control c = s.audio.controls[1];
  c.key = "membrane[0].radius";
  c.low = 0.25;
  c.high = 0.35;
  Result<audio::ParameterTable> t = build_parameter_table(kDrum, kSmall, s.model, s.settings, c);
  ASSERT_FALSE(t.ok());
  EXPECT_NE(t.error().message.find("initial positions"), std::string::npos)
      << t.error().to_string();
  EXPECT_GT(t.error().line, 0);
  EXPECT_EQ(t.error().key, "control[1].key");
}

TEST(Live, ControlGlidesToItsTargetAndNeverMakesANonFiniteSample) {
  const std::vector<std::string>& sets = kSmall;
  Scene s = scene_of(kDrum, sets);
  std::vector<audio::ParameterTable> tables(s.audio.controls.size());
  Result<audio::ParameterTable> t =
      build_parameter_table(kDrum, sets, s.model, s.settings, s.audio.controls[1]);
  ASSERT_TRUE(t.ok());
  tables[1] = t.value();
  Simulator sim(s.model, live_settings(s));
  audio::LiveSource src(sim, s.audio, 48000, tables, 64);
  std::vector<float> out(64);
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> u(-0.5f, 1.5f);  // beyond [0, 1] too: clamped
  src.control({0, 0, 1.0f});                             // a strike
  for (int block = 0; block < 1500; ++block) {  // 2 s at 48 kHz, a new target every 4 blocks
    if (block % 4 == 0) src.control({1, u(rng), 0});
    if (block % 50 == 0) src.control({0, 0, 1.0f});
    src.render(out.data(), out.size());
    for (const float y : out) ASSERT_TRUE(std::isfinite(y)) << "block " << block;
  }
  EXPECT_FALSE(src.blown_up());
  // A last target, held: after the glide (20 ms) every link has exactly the blend's stiffness.
  src.control({1, 1.0f, 0});
  for (int block = 0; block < 30; ++block) src.render(out.data(), out.size());
  EXPECT_DOUBLE_EQ(src.control_value(1), 33100.0);
  const LinkPoolBase& pool = *sim.model().links.pools()[0];
  for (std::size_t id = 0; id < pool.size(); ++id)
    ASSERT_DOUBLE_EQ(double(pool.param(id, 0)), 33100.0) << "link " << id;
}

TEST(Live, StrikeStartsAtTheNextSample) {
  Scene s = scene_of(kDrum, kSmall);
  s.audio.controls.resize(1);  // the strike alone
  Simulator sim(s.model, live_settings(s));
  audio::LiveSource src(sim, s.audio, 48000, {}, 64);
  std::vector<float> out(64);
  src.render(out.data(), 64);
  for (const float y : out) EXPECT_EQ(y, 0.0f);  // at rest: silence
  src.control({0, 0, 1.0f});
  src.render(out.data(), 64);
  double peak = 0;
  for (const float y : out) peak = std::max(peak, double(std::abs(y)));
  EXPECT_GT(peak, 1e-4);
}

// The playable bowed string: silent with the bow at rest; the speed control (CC 2) at 0.4 of
// its range (0.2 m/s, sound_bowed_string's bow speed) makes it sound at the string's
// fundamental (219.9 Hz plucked; a bowed string plays a little flat: 217.9 Hz offline), and
// the bow brought back to rest lets it fall silent.
TEST(Live, BowSpeedControlStartsAndStopsTheBowing) {
  const std::string bowed = std::string(MAILLE_SOURCE_DIR) + "/examples/play_bowed_string.toml";
  Scene s = scene_of(bowed, {});
  std::vector<audio::ParameterTable> tables(s.audio.controls.size());
  for (std::size_t c = 0; c < tables.size(); ++c) {
    Result<audio::ParameterTable> t =
        build_parameter_table(bowed, {}, s.model, s.settings, s.audio.controls[c]);
    ASSERT_TRUE(t.ok()) << t.error().to_string();
    tables[c] = t.value();
  }
  Simulator sim(s.model, live_settings(s));
  audio::LiveSource src(sim, s.audio, 48000, tables, 64);
  std::vector<float> out(48000);
  src.render(out.data(), 4800);
  for (std::size_t i = 0; i < 4800; ++i) ASSERT_EQ(out[i], 0.0f);  // the bow at rest
  src.control({0, 0.4f, 0.4f});                                    // 0.2 m/s
  src.render(out.data(), out.size());                              // 1 s of bowing
  const std::span<const float> late(out.data() + 24000, 24000);
  double rms = 0;
  for (const float y : late) rms += double(y) * y;
  rms = std::sqrt(rms / double(late.size()));
  EXPECT_GT(rms, 0.01);
  const double f = spectrum::dominant(late, 48000, 150, 300).frequency;
  EXPECT_NEAR(f, 219.9, 0.03 * 219.9) << "the bowed fundamental";
  src.control({0, 0.0f, 0.0f});  // the bow stops: its friction now damps the string
  src.render(out.data(), out.size());
  double after = 0;
  for (std::size_t i = 38400; i < 48000; ++i) after += double(out[i]) * out[i];
  after = std::sqrt(after / 9600.0);
  EXPECT_LT(after, 0.1 * rms) << "still sounding 0.8 s after the bow stopped";
  EXPECT_FALSE(src.blown_up());
}

// MIDI messages onto controls: a CC reaches its controller's controls on their channel (or
// any), a note-on places the key by its number and strikes by its velocity (a note-off or a
// note-on at velocity 0 does nothing), the pitch bend's 14 bits span [0, 1] with 8192 in the
// middle.
TEST(Live, MidiMessagesReachTheirControls) {
  audio::AudioSpec spec;
  spec.controls.resize(4);
  spec.controls[0].midi = audio::MidiSource::cc;
  spec.controls[0].midi_number = 74;
  spec.controls[1].midi = audio::MidiSource::cc;
  spec.controls[1].midi_number = 74;
  spec.controls[1].midi_channel = 2;
  spec.controls[2].midi = audio::MidiSource::note;
  spec.controls[3].midi = audio::MidiSource::pitchbend;
  audio::ControlEvent e[8];
  const unsigned char cc_ch1[] = {0xB0, 74, 127}, cc_ch2[] = {0xB1, 74, 0},
                      cc_other[] = {0xB0, 1, 5};
  ASSERT_EQ(audio::midi_events(spec, cc_ch1, 3, e, 8), 1u);  // channel 2's control not on 1
  EXPECT_EQ(e[0].control, 0u);
  EXPECT_EQ(e[0].value, 1.0f);
  ASSERT_EQ(audio::midi_events(spec, cc_ch2, 3, e, 8), 2u);  // any channel, and channel 2
  EXPECT_EQ(e[1].control, 1u);
  EXPECT_EQ(e[1].value, 0.0f);
  EXPECT_EQ(audio::midi_events(spec, cc_other, 3, e, 8), 0u);
  const unsigned char note[] = {0x95, 60, 100}, silent[] = {0x90, 60, 0}, off[] = {0x80, 60, 64};
  ASSERT_EQ(audio::midi_events(spec, note, 3, e, 8), 1u);
  EXPECT_EQ(e[0].control, 2u);
  EXPECT_EQ(e[0].value, 60.0f / 127.0f);
  EXPECT_EQ(e[0].strength, 100.0f / 127.0f);
  EXPECT_EQ(audio::midi_events(spec, silent, 3, e, 8), 0u);
  EXPECT_EQ(audio::midi_events(spec, off, 3, e, 8), 0u);
  const unsigned char low[] = {0xE0, 0, 0}, middle[] = {0xE0, 0, 64}, high[] = {0xE0, 127, 127};
  ASSERT_EQ(audio::midi_events(spec, low, 3, e, 8), 1u);
  EXPECT_EQ(e[0].value, 0.0f);
  ASSERT_EQ(audio::midi_events(spec, middle, 3, e, 8), 1u);
  EXPECT_NEAR(e[0].value, 0.5, 1e-4);
  ASSERT_EQ(audio::midi_events(spec, high, 3, e, 8), 1u);
  EXPECT_EQ(e[0].value, 1.0f);
  EXPECT_EQ(audio::midi_events(spec, cc_ch2, 3, e, 1), 1u);  // at most out_size
  EXPECT_EQ(audio::midi_events(spec, cc_ch1, 1, e, 8), 0u);  // a truncated message
}

// The friction link's hair velocity u (the playable bow's speed): a bow at rest whose hair moves
// at u rubs exactly as a bow point moving at u (w = v_b - (v_a + u)); u = 0 is the old law.
TEST(Live, FrictionHairVelocityIsTheBowsSpeed) {
  Friction::Params moving, hair;
  hair.hair_vx = Real(0.05);
  hair.hair_vz = Real(0.2);
  const Vec3 x{}, vb{Real(0.01), 0, Real(-0.03)}, u{Real(0.05), 0, Real(0.2)};
  const Vec3 f_moving = Friction::force(x, x, u, vb, moving);
  const Vec3 f_hair = Friction::force(x, x, Vec3{}, vb, hair);
  EXPECT_EQ(f_moving.x, f_hair.x);
  EXPECT_EQ(f_moving.y, f_hair.y);
  EXPECT_EQ(f_moving.z, f_hair.z);
  const Vec3 f_still = Friction::force(x, x, Vec3{}, vb, moving);  // u = 0: w = v_b
  const Real s = norm(vb);
  const Real expected = moving.normal_force * Friction::coefficient(s, moving) /
                        std::sqrt(s * s + moving.stick_velocity * moving.stick_velocity);
  EXPECT_NEAR(f_still.z, vb.z * expected, 1e-12);
}

}  // namespace
}  // namespace maille
