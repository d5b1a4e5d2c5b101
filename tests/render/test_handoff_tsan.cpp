// The physics/render hand-off under ThreadSanitizer: the viewer's PhysicsThread and the
// SnapshotExchange it publishes into, with a consumer thread taking snapshots the way the window
// does and a UI thread sending commands and moving a drag target at the same time. Built with
// -fsanitize=thread (its own target): any data race fails the run. The simulator runs with one
// thread (OpenMP's own synchronisation is invisible to TSan and would report false races).
#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <thread>

#include "maille/links/spring_damper.hpp"
#include "maille/render/snapshot_exchange.hpp"
#include "physics_thread.hpp"
#include "ring_player.hpp"

namespace maille::viewer {
namespace {

// The UI rounds each race runs against the physics thread (each a status read, a history read
// and one command): thousands of interleavings with the thread's steps.
constexpr int kUiRounds = 4000;

using namespace std::chrono_literals;

// A hanging chain of n beads: enough work per step for the threads to overlap.
Model chain(std::uint32_t n) {
  Model m;
  std::uint32_t prev = m.points.add(PointKind::fixed, 1, {0, 0, 0});
  for (std::uint32_t i = 1; i < n; ++i) {
    const auto p = m.points.add(PointKind::free, Real(0.01), {Real(0.05) * i, 0, 0});
    m.links.pool<SpringDamper>().add({prev, p}, {200, Real(0.05), Real(0.01)});
    prev = p;
  }
  return m;
}

TEST(Handoff, ReaderNeverSeesATornSnapshot) {
  render::SnapshotExchange exchange;
  constexpr std::uint64_t kFrames = 20000;
  std::atomic<bool> done{false};
  // Overlays and solids travel with the positions; a solid's mesh is shared, not copied.
  const auto mesh =
      std::make_shared<const TriMesh>(TriMesh{{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}}, {{0, 1, 2}}});
  std::thread writer([&] {
    Snapshot s;
    s.positions.resize(500);
    s.overlay.resize(3);
    s.surfaces.resize(2);
    for (auto& solid : s.surfaces) solid.mesh = mesh;
    for (std::uint64_t f = 1; f <= kFrames; ++f) {
      s.frame = f;
      for (auto& p : s.positions) p = {Real(f), Real(f), Real(f)};
      for (auto& seg : s.overlay) seg.a.x = Real(f);
      for (auto& solid : s.surfaces) solid.translation.x = Real(f);
      exchange.publish(s);
    }
    done = true;
  });
  std::uint64_t last = 0, taken = 0;
  while (!done || last < kFrames) {
    bool fresh = false;
    const Snapshot* s = exchange.take(&fresh);
    if (!s) continue;
    ASSERT_GE(s->frame, last);
    if (fresh) {
      ASSERT_GT(s->frame, last);
    }
    for (const auto& p : s->positions) ASSERT_EQ(p.x, Real(s->frame));  // one frame, whole
    ASSERT_EQ(s->overlay.size(), 3u);
    for (const auto& seg : s->overlay) ASSERT_EQ(seg.a.x, Real(s->frame));
    ASSERT_EQ(s->surfaces.size(), 2u);
    for (const auto& solid : s->surfaces) {
      ASSERT_EQ(solid.translation.x, Real(s->frame));
      ASSERT_EQ(solid.mesh, mesh);
    }
    last = s->frame;
    taken += fresh;
  }
  writer.join();
  EXPECT_EQ(last, kFrames);
  EXPECT_GT(taken, 0u);
}

TEST(Handoff, PhysicsThreadWithRendererAndUiThreads) {
  SimulationSettings settings;
  settings.step = 2e-4;
  settings.threads = 1;
  const Model model = chain(200);
  render::SnapshotExchange exchange;
  PhysicsThread physics(model, settings, exchange, /*play=*/true);
  physics.set_speed(0);  // as fast as possible: the most publications

  std::atomic<bool> stop{false};
  std::atomic<std::uint64_t> frames{0};
  // The "window": takes the latest snapshot, checks it, as the renderer would read it.
  std::thread renderer([&] {
    while (!stop) {
      bool fresh = false;
      if (const Snapshot* s = exchange.take(&fresh); s && fresh) {
        EXPECT_EQ(s->positions.size(), model.points.size());
        double sum = 0;
        for (const auto& p : s->positions) sum += p.y;
        EXPECT_TRUE(std::isfinite(sum));
        ++frames;
      }
      std::this_thread::sleep_for(1ms);
    }
  });

  // The "UI": every command the panels send, a drag with the mouse, status and plot reads.
  // A bounded number of UI rounds (not a duration: a busy machine only makes it slower).
  int round = 0;
  while (round < kUiRounds) {
    physics.status();
    physics.history();
    switch (round++ % 8) {
      case 0:
        physics.drag().grab({100, {1, 1, 0}, 5, Real(0.01)});
        break;
      case 1:
        physics.drag().move_to({2, 0, 1});
        break;
      case 2:
        physics.scale_link_param(0, 0, Real(1.1));
        break;
      case 3:
        physics.scale_link_param(0, 0, Real(1 / 1.1));
        break;
      case 4: {
        Fields f;
        f.air_drag = Real(0.1) * Real(round % 3);
        physics.set_fields(f);
        break;
      }
      case 5:
        physics.drag().release();
        break;
      case 6:
        physics.set_time_step(round % 16 < 8 ? 1e-4 : 2e-4);
        break;
      case 7:
        if (round % 64 == 7) {
          physics.step_once();
          physics.reset();
          physics.play();
        }
        break;
    }
    std::this_thread::sleep_for(2ms);
  }
  // The integrator is swapped around the running state, between two steps.
  physics.set_integrator("symplectic_euler");
  for (int i = 0; i < 500 && physics.status().integrator != "symplectic_euler"; ++i)
    std::this_thread::sleep_for(10ms);
  EXPECT_EQ(physics.status().notice, "");
  EXPECT_TRUE(physics.wait_for_step(physics.status().step + 10, 5));
  stop = true;
  renderer.join();
  EXPECT_GT(frames.load(), 10u);
  EXPECT_FALSE(physics.status().blow_up.has_value());
  EXPECT_EQ(physics.status().integrator, "symplectic_euler");
}

// Sound (docs/sound.md, "The viewer's Sound panel"): the physics thread renders a listened
// point into a RingPlayer's ring while a "device" thread takes periods from it as a callback
// would (gain changes included) and the UI sends the commands that make the physics build a new
// source (step, reset, scheme), stops and starts the sound. ring_player.cpp is compiled into
// this test: the ring's hand-off is checked too.
TEST(Handoff, PhysicsThreadWithSoundDeviceAndUi) {
  SimulationSettings settings;
  settings.step = 1.0 / 48000;
  settings.threads = 1;
  const Model model = chain(60);
  audio::AudioSpec spec;
  spec.listeners.push_back({"p30", 30, audio::Quantity::velocity, {0, 1, 0}});
  spec.settings.gain = 1;
  render::SnapshotExchange exchange;
  PhysicsThread physics(model, settings, exchange, /*play=*/true);
  auto player = std::make_shared<play::RingPlayer>(1, 48000, 2 * 256 + 480, 64, 0.0f);
  physics.start_sound({player, nullptr, spec, {}});

  std::atomic<bool> stop{false};
  std::atomic<std::uint64_t> periods{0};
  std::thread device([&] {
    std::vector<float> period(256);
    float* out[] = {period.data()};
    while (!stop) {
      player->process(out, period.size());
      for (const float y : period) EXPECT_TRUE(std::isfinite(y));
      ++periods;
      std::this_thread::sleep_for(5ms);  // about a 256-frame period at 48 kHz
    }
  });
  // A bounded number of UI rounds (not a duration: a busy machine only makes it slower).
  int round = 0;
  while (round < kUiRounds) {
    physics.status();
    player->counters(round % 2 == 0);
    switch (round++ % 6) {
      case 0:
        player->set_gain(float(round % 3) * 0.5f);
        break;
      case 1:
        physics.set_time_step(round % 12 < 6 ? 1.0 / 48000 : 1.0 / 44100);
        break;
      case 2:
        physics.drag().grab({20, {1, 1, 0}, 5, Real(0.01)});
        break;
      case 3:
        physics.drag().release();
        if (round % 24 == 4) physics.reset();
        break;
      case 4:
        physics.set_integrator(round % 12 < 6 ? "symplectic_euler" : "leapfrog");
        break;
      case 5:
        if (round % 36 == 6) {
          physics.stop_sound();
          physics.start_sound({player, nullptr, spec, {}});
        }
        break;
    }
    std::this_thread::sleep_for(3ms);
  }
  stop = true;
  device.join();
  physics.stop_sound();
  EXPECT_GT(periods.load(), 10u);
  EXPECT_GT(player->counters().rendered, 0u);
  EXPECT_FALSE(physics.status().blow_up.has_value());
}

}  // namespace
}  // namespace maille::viewer
