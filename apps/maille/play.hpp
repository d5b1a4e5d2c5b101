// `maille play`: a scene's [[listen]] channels streamed to an audio device in real time, its
// [[control]] tables played from MIDI and OSC (docs/sound.md, "Playing live").
//
//   MidiInput (RtMidi's thread) --ControlEvent ring--+
//   OscInput (its UDP thread)   --ControlEvent ring--+--> PlayEngine::process (the device's
//                                                          callback: controls, LiveSource::render,
//                                                          CPU time) --sample ring--> Recording
//                                                          (its thread; --record FILE.wav)
//   AudioOutput: JACK (directly) or RtAudio (ALSA, PulseAudio), calls process() per period.
#pragma once

#include <atomic>
#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include "maille/live.hpp"

namespace maille::app {

// Everything the audio callback touches. process() allocates nothing, takes no lock and does
// no I/O: the rings are fixed, the buffers sized before the stream starts.
struct PlayEngine {
  PlayEngine(audio::LiveSource& source, int rate, std::size_t max_frames, std::uint64_t frame_limit,
             bool record);

  // One period: `frames` samples of every channel into out[c] (one buffer per channel).
  void process(float* const* out, std::size_t frames);
  // The same, interleaved (RtAudio).
  void process_interleaved(float* out, std::size_t frames);

  audio::LiveSource& source;
  int rate;
  std::size_t channels;
  std::uint64_t frame_limit;  // --duration in frames; 0: until stopped
  std::vector<float> block;   // interleaved, max_frames x channels
  audio::SpscRing<audio::ControlEvent, 1024> midi_events, osc_events;
  // The samples sent, for --record (null without it). 2^20 samples: 11 s of stereo at 48 kHz
  // of slack for the writer thread, which drains it every 20 ms.
  std::unique_ptr<audio::SpscRing<float, (1 << 20)>> sent;
  std::atomic<std::uint64_t> record_dropped{0};

  std::atomic<std::uint64_t> frames_played{0};
  std::atomic<std::uint64_t> xruns{0};
  std::atomic<bool> finished{false};  // frame_limit reached, or the model blew up
  // Each period's computing time over the period's duration: the CPU time of the callback's
  // thread (CLOCK_THREAD_CPUTIME_ID: time the thread was not running does not count) and the
  // wall time (which, with --threads > 1, also covers the other threads' share).
  struct Fractions {
    double max = 0, sum = 0;
    std::uint64_t count = 0;
    static constexpr int kBins = 800;  // 0.5 % of a period each, up to 4 periods
    std::vector<std::uint32_t> bins = std::vector<std::uint32_t>(kBins + 1, 0);
    void add(double fraction);
    double mean() const { return count ? sum / double(count) : 0.0; }
    double percentile(double p) const;  // the upper edge of the bin where p is reached
  };
  Fractions cpu, wall;

 private:
  void account(double cpu_seconds, double wall_seconds, std::size_t frames);
};

// The device side. open_*() return nullptr and say why in `why` when they cannot start.
class AudioOutput {
 public:
  virtual ~AudioOutput() = default;
  virtual std::string describe() const = 0;  // "JACK (server default, client maille)"
  virtual double latency_seconds() const = 0;
  virtual int rate() const = 0;
  virtual std::size_t buffer() const = 0;  // frames per period
  virtual void stop() = 0;
};

struct OutputRequest {
  std::string driver;  // "jack", "alsa", "pulse"; empty: JACK, then PulseAudio, then ALSA
  std::string device;  // empty: the default
  int rate = 48000;
  std::size_t buffer = 64;
  std::size_t channels = 1;
  std::string client = "maille";  // JACK client name
};

// Opens the device; `make_engine(rate, buffer)` is called once the stream's rate and period are
// known and before it starts. Returns nullptr with every attempt's reason in `tried`.
using EngineFactory = std::function<PlayEngine*(int rate, std::size_t buffer)>;
std::unique_ptr<AudioOutput> open_output(const OutputRequest& r, const EngineFactory& make_engine,
                                         std::vector<std::string>& tried);
std::unique_ptr<AudioOutput> open_jack(const OutputRequest& r, const EngineFactory& make_engine,
                                       std::string& why);
std::unique_ptr<AudioOutput> open_rtaudio(const OutputRequest& r, const EngineFactory& make_engine,
                                          std::string& why);

// Control inputs: they push ControlEvents into the engine's rings from their own threads.
class ControlInput {
 public:
  virtual ~ControlInput() = default;
  virtual std::string describe() const = 0;
};
// A virtual MIDI input port named `port`, on JACK MIDI when `jack`, else the ALSA sequencer.
std::unique_ptr<ControlInput> open_midi(const audio::AudioSpec& spec, PlayEngine& engine, bool jack,
                                        std::string& why);
// An OSC server (UDP) on spec.settings.osc_host : osc_port.
std::unique_ptr<ControlInput> open_osc(const audio::AudioSpec& spec, PlayEngine& engine,
                                       std::string& why);

// --record: drains the engine's ring from its own thread into memory, written as a float32 WAV
// at the end (exactly the samples sent).
class Recording {
 public:
  Recording(PlayEngine& engine);
  ~Recording();
  std::vector<std::vector<float>> finish();  // stops the thread; one vector per channel

 private:
  void drain();
  PlayEngine& engine_;
  std::vector<float> interleaved_;
  std::atomic<bool> stop_{false};
  std::thread thread_;
};

}  // namespace maille::app
