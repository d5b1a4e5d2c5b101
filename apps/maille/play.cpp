// `maille play SCENE`: the scene's [[listen]] channels to an audio device in real time, until
// Ctrl-C or --duration; its [[control]] tables from MIDI and OSC; --record; --benchmark (the CPU
// time per period with no device). docs/sound.md, "Playing live".
#include <pthread.h>
#include <chrono>
#include <csignal>
#include <cstdio>
#include <iostream>
#include <optional>
#include <thread>

#include "commands.hpp"
#include "maille/live.hpp"
#include "maille/scene.hpp"
#include "maille/simulator.hpp"
#include "maille/wav.hpp"
#include "play_engine.hpp"

namespace maille::app {

namespace {

using play::AudioOutput;
using play::ControlInput;
using play::OutputRequest;
using play::PlayEngine;
using play::Recording;

std::atomic<bool> g_stop_play{false};

// Steps between the simulator's health checks while playing: every sample is checked finite
// (LiveSource), so a pass over every point per step is not needed to stop a blow-up's sound;
// within 64 steps the model is stopped and the summary says when.
constexpr int kHealthEvery = 64;

// Ctrl-C and SIGTERM are blocked before any thread starts (JACK's, RtMidi's, the OSC server's:
// they inherit the mask, so a signal never interrupts one of them in a system call) and taken
// by the main thread alone, which waits for them (stopped_by_signal) while the model plays.
sigset_t stop_signals() {
  sigset_t set;
  sigemptyset(&set);
  sigaddset(&set, SIGINT);
  sigaddset(&set, SIGTERM);
  return set;
}

// Waits up to `ms` milliseconds for Ctrl-C or SIGTERM; true when one came.
bool stopped_by_signal(int ms) {
  const sigset_t set = stop_signals();
  timespec t{0, long(ms) * 1000000L};
  if (sigtimedwait(&set, nullptr, &t) > 0) g_stop_play = true;
  return g_stop_play;
}

// What the audio callback plays, made once the device's rate and period are known.
struct Instrument {
  std::optional<Simulator> sim;
  std::optional<audio::LiveSource> source;
  std::optional<PlayEngine> engine;
};

std::string location(const audio::Control& c, const std::string& key) {
  return c.file + ":" + std::to_string(c.line) + ":" + std::to_string(c.column) + ": error: key '" +
         c.name + "." + key + "': ";
}

void print_summary(const PlayEngine& e, std::size_t period, double latency) {
  const double frames = double(e.frames_played.load());
  std::printf(
      "maille: played %llu frames (%.3f s at %d Hz), xruns %llu, CPU per period: mean %.1f %%, "
      "largest %.1f %%, p99 %.1f %% of the %zu-frame period (%.3f ms), latency %.2f ms\n",
      static_cast<unsigned long long>(frames), frames / e.rate, e.rate,
      static_cast<unsigned long long>(e.xruns.load()), 100 * e.cpu.mean(), 100 * e.cpu.max,
      100 * e.cpu.percentile(0.99), period, 1e3 * double(period) / e.rate, 1e3 * latency);
}

int benchmark(Instrument& in, const PlayOptions& o) {
  const double seconds = o.duration ? *o.duration : 5.0;
  const std::size_t period = o.buffer;
  const std::uint64_t periods = static_cast<std::uint64_t>(seconds * o.rate / double(period));
  std::vector<std::vector<float>> out(in.source->channels(), std::vector<float>(period));
  std::vector<float*> ptr;
  for (auto& c : out) ptr.push_back(c.data());
  for (std::uint64_t p = 0; p < periods && !(p % 1024 == 0 && stopped_by_signal(0)); ++p)
    in.engine->process(ptr.data(), period);
  const PlayEngine& e = *in.engine;
  std::printf(
      "maille: benchmark %s: %llu periods of %zu frames at %d Hz (%.3f ms), %d thread%s: CPU "
      "time per period (CLOCK_THREAD_CPUTIME_ID) mean %.1f %%, p99 %.1f %%, largest %.1f %% of "
      "the period; wall time mean %.1f %%, p99 %.1f %%; %s\n",
      o.scene.c_str(), static_cast<unsigned long long>(e.cpu.count), period, o.rate,
      1e3 * double(period) / o.rate, in.sim->threads(), in.sim->threads() == 1 ? "" : "s",
      100 * e.cpu.mean(), 100 * e.cpu.percentile(0.99), 100 * e.cpu.max, 100 * e.wall.mean(),
      100 * e.wall.percentile(0.99), e.source.blown_up() ? "the model BLEW UP" : "no blow-up");
  return e.source.blown_up() ? blow_up : ok;
}

}  // namespace

int play(const PlayOptions& o) {
  const sigset_t blocked = stop_signals();
  pthread_sigmask(SIG_BLOCK, &blocked, nullptr);
  Result<Scene> loaded = load_scene(o.scene, o.sets);
  if (!loaded) {
    std::cerr << loaded.error().to_string() << '\n';
    return bad_input;
  }
  Scene& scene = loaded.value();
  if (scene.audio.listeners.empty()) {
    std::cerr << o.scene << ": error: play: the scene has no [[listen]] table (docs/sound.md)\n";
    return bad_input;
  }
  for (const audio::Control& c : scene.audio.controls)
    if (!c.osc.empty() && scene.audio.settings.osc_port == 0) {
      std::cerr << location(c, "osc") << "listens on OSC " << c.osc
                << ": give [audio] osc_port (the UDP port to listen on)\n";
      return bad_input;
    }
  SimulationSettings settings = scene.settings;
  settings.threads = o.threads ? *o.threads : 1;
  settings.publish_every = kNeverEvery;  // no snapshots, no energy samples at audio rate
  settings.sample_every = kNeverEvery;
  if (settings.backend != "cpu") {
    std::cerr << o.scene << ": error: play reads the state on the host at every sample: the "
              << settings.backend << " backend cannot play (use cpu)\n";
    return bad_input;
  }
  // Every parameter control's key, read at values across its range and validated.
  std::vector<audio::ParameterTable> tables(scene.audio.controls.size());
  for (std::size_t c = 0; c < tables.size(); ++c) {
    if (scene.audio.controls[c].key.empty()) continue;
    Result<audio::ParameterTable> t =
        build_parameter_table(o.scene, o.sets, scene.model, settings, scene.audio.controls[c]);
    if (!t) {
      std::cerr << t.error().to_string() << '\n';
      return bad_input;
    }
    tables[c] = std::move(t.value());
  }

  Instrument in;
  auto make = [&](int rate, std::size_t buffer) -> PlayEngine* {  // a play::CallbackFactory
    try {
      in.engine.reset();
      in.source.reset();
      in.sim.emplace(scene.model, settings);
      in.sim->set_stage_timing(Simulator::StageTiming::sampled_steps);  // no clock per step
      in.sim->set_health_every(kHealthEvery);
      in.source.emplace(*in.sim, scene.audio, rate, tables, buffer);
      const std::uint64_t limit =
          o.duration ? static_cast<std::uint64_t>(std::llround(*o.duration * rate)) : 0;
      in.engine.emplace(*in.source, rate, buffer, limit, !o.record.empty());
      return &*in.engine;
    } catch (const std::exception& e) {
      std::cerr << o.scene << ": error: " << e.what() << '\n';
      return nullptr;
    }
  };
  if (o.benchmark) {
    if (!make(o.rate, o.buffer)) return bad_input;
    return benchmark(in, o);
  }

  OutputRequest request;
  request.driver = o.driver;
  request.device = o.device;
  request.rate = o.rate;
  request.buffer = o.buffer;
  request.channels = scene.audio.listeners.size();
  std::vector<std::string> tried;
  std::unique_ptr<AudioOutput> output = play::open_output(request, make, tried);
  if (!output) {
    std::cerr << "maille play: error: no audio output could be opened; tried:\n";
    for (const std::string& t : tried) std::cerr << "  " << t << '\n';
    std::cerr << "(start a JACK server, or PulseAudio / PipeWire, or name an ALSA device; "
                 "docs/sound.md \"Playing live\")\n";
    return bad_input;
  }
  PlayEngine& engine = *in.engine;
  std::optional<Recording> recording;
  if (!o.record.empty()) recording.emplace(engine);

  // Controls: MIDI through the same server as the audio when it is JACK.
  std::vector<std::unique_ptr<ControlInput>> inputs;
  bool midi = false, osc = false;
  for (const audio::Control& c : scene.audio.controls) {
    midi = midi || c.midi != audio::MidiSource::none;
    osc = osc || !c.osc.empty();
  }
  const bool on_jack = output->is_jack();
  std::string why;
  if (midi) {
    if (auto m = play::open_midi(scene.audio, engine.controls, on_jack, why))
      inputs.push_back(std::move(m));
    else
      std::cerr << "maille: warning: the MIDI controls are off: " << why << '\n';
  }
  if (osc) {
    if (auto s = play::open_osc(scene.audio, engine.controls, why))
      inputs.push_back(std::move(s));
    else
      std::cerr << "maille: warning: the OSC controls are off: " << why << '\n';
  }
  std::printf("maille: playing %s on %s: %d Hz, %zu frames per period, %zu channel%s, %s%s\n",
              o.scene.c_str(), output->describe().c_str(), output->rate(), output->buffer(),
              request.channels, request.channels == 1 ? "" : "s",
              in.source->plan().describe().c_str(), o.duration ? "" : "; Ctrl-C to stop");
  for (const auto& i : inputs) std::printf("maille: controls: %s\n", i->describe().c_str());
  for (std::size_t c = 0; c < tables.size(); ++c)
    if (tables[c].rows)
      std::printf("maille: %s: %s in [%g, %g]: %zu values of the model, %s\n",
                  scene.audio.controls[c].name.c_str(), scene.audio.controls[c].key.c_str(),
                  scene.audio.controls[c].low, scene.audio.controls[c].high, tables[c].slots.size(),
                  tables[c].rows == 2
                      ? "linear in the key"
                      : ("33 rows (blend error " + std::to_string(tables[c].max_blend_error) + ")")
                            .c_str());
  std::fflush(stdout);
  while (!stopped_by_signal(10) && !engine.finished.load(std::memory_order_acquire)) {
  }
  const double latency = output->latency_seconds();
  output->stop();
  inputs.clear();
  print_summary(engine, output->buffer(), latency);
  if (recording) {
    const std::vector<std::vector<float>> sent = recording->finish();
    try {
      const WavReport r = write_wav(o.record, sent, engine.rate, audio::SampleFormat::float32,
                                    std::vector<double>(sent.size(), 1.0));
      std::printf("maille: recorded %s: %llu frames, float32, the samples sent%s\n",
                  o.record.c_str(), static_cast<unsigned long long>(r.frames),
                  engine.record_dropped ? " (SOME DROPPED: the writer fell behind)" : "");
    } catch (const std::exception& e) {
      std::cerr << "error: --record " << o.record << ": " << e.what() << '\n';
      return output_error;
    }
  }
  if (in.source->blown_up()) {
    std::fprintf(stderr,
                 "maille: the model blew up at t = %.6f s (a non-finite sample): silence "
                 "from there on\n",
                 in.source->blow_up_time());
    return blow_up;
  }
  if (in.source->clipped())
    std::printf("maille: %llu samples beyond full scale (lower [audio] gain)\n",
                static_cast<unsigned long long>(in.source->clipped()));
  return ok;
}

}  // namespace maille::app
