// The viewer's audio path without a sound card (docs/sound.md, "The viewer's Sound panel"): the
// viewer's PhysicsThread renders the scene's [[listen]] channels through a LiveSource into a
// RingPlayer's ring, paced by the ring; this test plays the device, taking periods from the
// callback whenever the ring holds one (as JACK's freewheel mode would: no deadline). What comes
// out equals what `maille run --audio` writes as float32 (the Recorder), sample for sample,
// when nothing is dragged. And the sound goes on, with no dangling stage, through the changes the
// panels make (a reset, a new scheme, a new step, parameters).
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <functional>
#include <thread>

#include "maille/render/snapshot_exchange.hpp"
#include "maille/scene.hpp"
#include "physics_thread.hpp"
#include "ring_player.hpp"

namespace maille::viewer {
namespace {

using namespace std::chrono_literals;

const std::string kString = std::string(MAILLE_SOURCE_DIR) + "/examples/sound_plucked_string.toml";
// One step per sample at 48 kHz, a fixed gain, float32: the cli.play_jack_equal set-up.
const std::vector<std::string> kExact{"simulation.step=2.0833333333333333e-05", "audio.rate=48000",
                                      "audio.gain=0.1", "audio.format=float32"};

Scene scene_of(const std::string& path, const std::vector<std::string>& sets) {
  Result<Scene> s = load_scene(path, sets);
  EXPECT_TRUE(s.ok()) << (s.ok() ? "" : s.error().to_string());
  return std::move(s.value());
}

// The device: periods of `period` frames taken from the player whenever its ring holds one,
// until `frames` frames are gathered (or 60 s pass: a stalled producer fails, never hangs).
std::vector<std::vector<float>> play_periods(play::RingPlayer& player, std::size_t frames,
                                             std::size_t period = 256) {
  const std::size_t n = player.channels();
  std::vector<std::vector<float>> out(n, std::vector<float>(frames));
  std::vector<float*> ptr(n);
  // A stall guard counted in polls, not read from the clock: 300,000 empty polls in a row
  // (at least 60 s of 200 us sleeps) with no frame.
  long empty = 0;
  constexpr long kMaxEmptyPolls = 300000;
  for (std::size_t f = 0; f < frames && empty < kMaxEmptyPolls;) {
    const std::size_t take = std::min(period, frames - f);
    if (player.ring().size() < take) {
      ++empty;
      std::this_thread::sleep_for(200us);
      continue;
    }
    empty = 0;
    for (std::size_t c = 0; c < n; ++c) ptr[c] = out[c].data() + f;
    player.process(ptr.data(), take);
    f += take;
  }
  if (empty >= kMaxEmptyPolls) ADD_FAILURE() << "the ring stalled: no frame in 300,000 polls";
  return out;
}

TEST(ViewerSound, RingGivesTheSamplesOfRunAudio) {
  Scene a = scene_of(kString, kExact), b = scene_of(kString, kExact);
  const std::size_t frames = 48000;  // 1 s
  // `maille run --audio`: the Recorder on a simulator of the scene as read.
  Simulator offline(a.model, a.settings);
  audio::Recorder rec(a.audio, a.settings.step);
  rec.attach(offline);
  ASSERT_TRUE(offline.run_steps(frames));
  rec.finish();

  render::SnapshotExchange exchange;
  PhysicsThread physics(b.model, b.settings, exchange, /*play=*/false);
  auto player = std::make_shared<play::RingPlayer>(2, 48000, 2 * 256 + 480, 64);
  physics.start_sound({player, nullptr, b.audio, {}});
  physics.play();
  const auto out = play_periods(*player, frames);
  physics.stop_sound();
  EXPECT_TRUE(physics.status().sound_notice.empty()) << physics.status().sound_notice;
  for (std::size_t c = 0; c < 2; ++c)
    for (std::size_t f = 0; f < frames; ++f)
      ASSERT_EQ(out[c][f], static_cast<float>(0.1 * double(rec.channels()[c][f])))
          << "channel " << c << " frame " << f;
}

// The panels' changes while sound plays: each makes the physics build a new source on the
// simulator (a reset, a scheme, a step that the rate does not divide: resampled), parameters
// are edited under it; the sound goes on (new frames keep coming, all finite), nothing dangles
// (this runs under ASan in the asan preset) and the status says sound is on.
TEST(ViewerSound, GoesOnThroughResetSchemeStepAndParameters) {
  Scene b = scene_of(kString, kExact);
  render::SnapshotExchange exchange;
  PhysicsThread physics(b.model, b.settings, exchange, /*play=*/true);
  auto player = std::make_shared<play::RingPlayer>(2, 48000, 2 * 256 + 480, 64);
  physics.start_sound({player, nullptr, b.audio, {}});
  const std::function<void()> changes[] = {
      [&] { physics.reset(); },
      [&] { physics.set_integrator("symplectic_euler"); },
      [&] { physics.set_time_step(1.0 / 44100); },  // resampled from here
      [&] { physics.scale_link_param(0, 0, Real(1.1)); },
      [&] {
        Fields f = b.model.fields;
        f.air_drag = 0.5;
        physics.set_fields(f);
      },
      [&] { physics.set_integrator("leapfrog"); },
  };
  for (const auto& change : changes) {
    change();
    const auto out = play_periods(*player, 5120);
    for (const auto& channel : out)
      for (const float y : channel) ASSERT_TRUE(std::isfinite(y));
    const PhysicsStatus st = physics.status();
    EXPECT_TRUE(st.sound) << st.sound_notice;
    EXPECT_TRUE(st.notice.empty()) << st.notice;
  }
  const std::uint64_t played = player->counters().frames_played;
  EXPECT_EQ(played, 6u * 5120u);
  physics.stop_sound();
  // Back to the wall clock: the model goes on without the ring.
  const std::uint64_t step = physics.status().step;
  EXPECT_TRUE(physics.wait_for_step(step + 100, 30));
}

// [[control]] in the viewer: events pushed into the ControlRings (as the OSC server's and the
// MIDI port's threads push them) reach the model through the physics thread. The small drum at
// rest is silent; a strike sounds within the ring's lead; the tension control, with its table,
// glides without a non-finite sample.
TEST(ViewerSound, ControlsReachTheModel) {
  const std::string drum = std::string(MAILLE_SOURCE_DIR) + "/examples/play_drum.toml";
  const std::vector<std::string> small{"membrane[0].rings=6", "listen[0].point=skin:45",
                                       "control[0].excite.point=skin:35"};
  Scene b = scene_of(drum, small);
  std::vector<audio::ParameterTable> tables(b.audio.controls.size());
  Result<audio::ParameterTable> t =
      build_parameter_table(drum, small, b.model, b.settings, b.audio.controls[1]);
  ASSERT_TRUE(t.ok()) << t.error().to_string();
  tables[1] = t.value();
  render::SnapshotExchange exchange;
  PhysicsThread physics(b.model, b.settings, exchange, /*play=*/true);
  auto player = std::make_shared<play::RingPlayer>(1, 48000, 2 * 256 + 480, 64);
  auto controls = std::make_shared<play::ControlRings>();
  physics.start_sound({player, controls, b.audio, tables});
  const auto peak = [](const std::vector<float>& x) {
    float p = 0;
    for (const float y : x) {
      EXPECT_TRUE(std::isfinite(y));
      p = std::max(p, std::abs(y));
    }
    return p;
  };
  EXPECT_EQ(peak(play_periods(*player, 4800)[0]), 0.0f);  // at rest: silence
  controls->osc.push({0, 0, 1.0f});                       // the strike, full strength
  controls->midi.push({1, 1.0f, 1.0f});                   // the tension to the top
  const float struck = peak(play_periods(*player, 9600)[0]);
  EXPECT_GT(struck, 1e-4f);
  EXPECT_TRUE(physics.status().sound_notice.empty()) << physics.status().sound_notice;
  physics.stop_sound();
}

// A drag is heard: the playable string at rest is silent; bead 8 grabbed by the mouse's spring
// and pulled 3 mm aside sounds at the listened bead 3 (within the ring's lead); let go, it
// rings.
TEST(ViewerSound, DragIsHeard) {
  const std::string path = std::string(MAILLE_SOURCE_DIR) + "/examples/play_string.toml";
  Scene b = scene_of(path, {});
  b.audio.controls.clear();  // the mouse alone
  render::SnapshotExchange exchange;
  PhysicsThread physics(b.model, b.settings, exchange, /*play=*/true);
  auto player = std::make_shared<play::RingPlayer>(1, 48000, 2 * 256 + 480, 64);
  physics.start_sound({player, nullptr, b.audio, {}});
  const auto peak = [](const std::vector<float>& x) {
    float p = 0;
    for (const float y : x) p = std::max(p, std::abs(y));
    return p;
  };
  EXPECT_EQ(peak(play_periods(*player, 4800)[0]), 0.0f);      // at rest: silence
  const std::uint32_t bead = b.audio.listeners[0].point + 5;  // string:8
  ASSERT_GT(b.model.points.inv_mass[bead], 0);
  const Vec3 x0 = b.model.points.initial_position[bead];
  // The panel's drag stiffness at its top (100x): the default spring holds the model's weight,
  // under which a string at 390 N hardly moves.
  DragTarget d = default_drag(b.model, b.settings.step, bead, x0 + Vec3{0, 0.003, 0});
  d.stiffness *= 100;
  physics.drag().grab(d);
  const float pulled = peak(play_periods(*player, 4800)[0]);
  physics.drag().release();
  const float ringing = peak(play_periods(*player, 4800)[0]);
  EXPECT_GT(pulled, 1e-4f);   // measured 4.4e-4 (0.05 per m/s: 9 mm/s at bead 3)
  EXPECT_GT(ringing, 1e-4f);  // measured 7.1e-4
  physics.stop_sound();
}

// The gain (the panel's slider) is smoothed in the callback: a change is a linear ramp of
// kGainRamp (960 samples at 48 kHz) from wherever the gain is, no sample moves by more than the
// ramp's step, and it lands exactly on the target. A change during a ramp starts a new ramp
// from the gain reached. An empty ring plays silence and counts an xrun while the model plays.
TEST(ViewerSound, GainRampsWithoutAStepAndEmptyRingIsSilence) {
  play::RingPlayer player(1, 48000, 8192, 64);
  const std::vector<float> ones(8192, 1.0f);
  ASSERT_EQ(player.ring().write(ones.data(), ones.size()), ones.size());
  std::vector<float> out(4096);
  float* ptr[] = {out.data()};
  player.set_gain(0.5f);
  player.process(ptr, 2048);
  const std::size_t ramp = static_cast<std::size_t>(play::RingPlayer::kGainRamp * 48000);
  const float step = 0.5f / float(ramp);
  EXPECT_NEAR(out[0], 1.0f - step, 1e-6f);
  for (std::size_t i = 1; i < 2048; ++i) {
    ASSERT_LE(out[i], out[i - 1]) << i;  // monotonic
    ASSERT_LE(out[i - 1] - out[i], step * 1.001f) << i;
  }
  EXPECT_EQ(out[ramp - 1], 0.5f);  // exactly the target at the ramp's end
  EXPECT_EQ(out[2047], 0.5f);
  player.process(ptr, 100);  // at 0.5
  player.set_gain(2.0f);     // up again, from 0.5
  player.process(ptr, 480);  // half the ramp
  EXPECT_NEAR(out[479], 0.5f + 1.5f * 480.0f / float(ramp), 1e-4f);
  player.set_gain(0.0f);  // mid-ramp: down from where it is, no jump
  const float reached = out[479];
  player.process(ptr, 4096);
  EXPECT_NEAR(out[0], reached - reached / float(ramp), 1e-4f);
  EXPECT_EQ(out[ramp - 1], 0.0f);
  // The ring runs dry (8192 frames in all): silence; an xrun only while the model plays.
  player.process(ptr, 4096);
  ASSERT_EQ(player.ring().size(), 0u);
  const auto before = player.counters().underruns;
  player.process(ptr, 256);
  EXPECT_EQ(player.counters().underruns, before);  // paused: not an xrun
  player.set_producing(true);
  player.process(ptr, 256);
  EXPECT_EQ(player.counters().underruns, before + 1);
  for (std::size_t i = 0; i < 256; ++i) ASSERT_EQ(out[i], 0.0f);
}

}  // namespace
}  // namespace maille::viewer
