// `maille play`'s audio callback: the model computed in the device's callback itself
// (docs/sound.md, "Playing live").
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
#include <memory>
#include <thread>
#include <vector>

#include "audio_output.hpp"
#include "controls.hpp"
#include "maille/live.hpp"

namespace maille::play {

// Each period's computing time over the period's duration, as fractions: mean, largest and a
// histogram for percentiles.
struct Fractions {
  double max = 0, sum = 0;
  std::uint64_t count = 0;
  static constexpr int kBins = 800;  // 0.5 % of a period each, up to 4 periods
  std::vector<std::uint32_t> bins = std::vector<std::uint32_t>(kBins + 1, 0);
  void add(double fraction);
  double mean() const { return count ? sum / double(count) : 0.0; }
  double percentile(double p) const;  // the upper edge of the bin where p is reached
};

// The CPU time of the calling thread (CLOCK_THREAD_CPUTIME_ID) and the monotonic wall clock, s.
double thread_cpu_seconds();
double wall_seconds();

// Everything the audio callback touches. process() allocates nothing, takes no lock and does
// no I/O: the rings are fixed, the buffers sized before the stream starts.
struct PlayEngine final : AudioCallback {
  PlayEngine(audio::LiveSource& source, int rate, std::size_t max_frames, std::uint64_t frame_limit,
             bool record);

  // One period: `frames` samples of every channel into out[c] (one buffer per channel).
  void process(float* const* out, std::size_t frames) override;
  // The same, interleaved (RtAudio), in pieces of the block's size.
  void process_interleaved(float* out, std::size_t frames) override;
  void xrun() override { xruns.fetch_add(1, std::memory_order_relaxed); }

  audio::LiveSource& source;
  int rate;
  std::size_t channels;
  std::uint64_t frame_limit;  // --duration in frames; 0: until stopped
  std::vector<float> block;   // interleaved, max_frames x channels
  ControlRings controls;
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
  Fractions cpu, wall;

 private:
  void period_interleaved(float* out, std::size_t frames);  // frames <= the block's
  void account(double cpu_s, double wall_s, std::size_t frames);
};

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

}  // namespace maille::play
