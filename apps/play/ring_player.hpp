// The viewer's audio path (docs/sound.md, "The viewer's Sound panel"): the physics thread, which
// owns the simulator, renders blocks through a LiveSource into a lock-free ring of frames, paced
// by the ring's fill level (fill); the device's callback only copies from the ring (process):
//
//   physics thread: controls (ControlRings) -> LiveSource::render(block) -> FrameRing::write
//   device callback: FrameRing::read -> the smoothed gain -> the device's buffers
//
// An empty ring while the model plays is an xrun: the callback plays silence for what is
// missing and counts it. While the model is paused (producing() false) the callback plays
// silence and counts nothing. No allocation, lock or I/O in process(); none in fill() either
// once the LiveSource has rendered its first block.
#pragma once

#include <algorithm>
#include <atomic>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "audio_output.hpp"
#include "controls.hpp"

namespace maille::play {

// Interleaved frames of a fixed channel count, one producer and one consumer, lock-free; the
// capacity (frames) is a power of two.
class FrameRing {
 public:
  FrameRing(std::size_t channels, std::size_t min_capacity);
  std::size_t channels() const { return channels_; }
  std::size_t capacity() const { return mask_ + 1; }
  std::size_t size() const;  // frames that can be read now
  // Producer: up to `frames` frames from `in` (interleaved); returns how many fitted.
  std::size_t write(const float* in, std::size_t frames);
  // Consumer: up to `frames` frames into out[c][offset + i] (one buffer per channel), times
  // `gain(i)`; returns how many there were.
  template <class Gain>
  std::size_t read(float* const* out, std::size_t offset, std::size_t frames, Gain&& gain);
  // Consumer, interleaved.
  template <class Gain>
  std::size_t read_interleaved(float* out, std::size_t frames, Gain&& gain);

 private:
  std::size_t channels_, mask_;
  std::vector<float> data_;  // capacity x channels
  alignas(64) std::atomic<std::size_t> write_{0};
  alignas(64) std::atomic<std::size_t> read_{0};
  static_assert(std::atomic<std::size_t>::is_always_lock_free);
};

class RingPlayer final : public AudioCallback {
 public:
  // `lead`: the frames the producer keeps in the ring (the latency it adds); `block`: the frames
  // it renders at a time (controls are applied between blocks); `gain`: the gain the callback
  // starts with (the viewer starts at 0 and ramps to its gain: no click at the start).
  static constexpr double kGainRamp = 0.02;  // s: a gain change is a linear ramp this long
  RingPlayer(std::size_t channels, int rate, std::size_t lead, std::size_t block = 64,
             float gain = 1.0f);

  // --- device side (the callback's thread)
  void process(float* const* out, std::size_t frames) override;
  void process_interleaved(float* out, std::size_t frames) override;
  void xrun() override { driver_xruns_.fetch_add(1, std::memory_order_relaxed); }

  // --- producer side (the physics thread)
  // Renders blocks of `source` into the ring until it holds `lead` frames, or after `budget`
  // seconds of wall time (the producer has other work: snapshots, commands); controls are
  // drained before each block when given. Returns the frames rendered. Measures the thread's
  // CPU time per block. `source` renders at most block() frames at a time.
  std::size_t fill(audio::LiveSource& source, ControlRings* controls, double budget = 1e9);
  // The model plays (the producer keeps the ring filled): an empty ring is then an xrun.
  void set_producing(bool producing) { producing_.store(producing, std::memory_order_release); }
  // Seconds until the ring falls to half its lead (the producer may sleep that long).
  double seconds_of_slack() const;

  // --- anyone
  void set_gain(float gain) { gain_target_.store(gain, std::memory_order_relaxed); }
  FrameRing& ring() { return ring_; }
  std::size_t channels() const { return ring_.channels(); }
  int rate() const { return rate_; }
  std::size_t lead() const { return lead_; }
  std::size_t block() const { return block_frames_; }

  struct Counters {
    std::uint64_t frames_played = 0;  // frames the device took (silence included)
    std::uint64_t underruns = 0;      // periods the ring could not fill while the model played
    std::uint64_t driver_xruns = 0;   // the driver's own (JACK's xrun callback, RtAudio's flag)
    std::uint64_t clipped = 0;        // samples sent beyond [-1, 1]
    std::uint64_t rendered = 0;       // frames the producer rendered
    double cpu_seconds = 0;           // the producer thread's CPU time rendering them
    double worst_block = 0;  // the largest block's CPU time over its duration since the last take
  };
  // The counters; `take_worst` resets the worst block (the panel reads it every half second).
  Counters counters(bool take_worst = false);

 private:
  float next_gain();  // one sample of the ramp (callback)
  void start_period();
  void end_period(std::size_t frames, std::size_t got, std::uint64_t clipped);

  FrameRing ring_;
  int rate_;
  std::size_t lead_, block_frames_;
  std::vector<float> block_;  // the producer's block, interleaved
  std::atomic<bool> producing_{false};
  std::atomic<float> gain_target_{1.0f};
  // The callback's own gain ramp (callback thread only).
  float gain_ = 1.0f, ramp_from_ = 1.0f, ramp_to_ = 1.0f;
  std::uint32_t ramp_length_ = 1, ramp_done_ = 0;  // samples; done == length: not ramping
  std::atomic<std::uint64_t> frames_played_{0}, underruns_{0}, driver_xruns_{0}, clipped_{0};
  std::atomic<std::uint64_t> rendered_{0};
  std::atomic<double> cpu_seconds_{0}, worst_block_{0};
};

// ---- FrameRing's reads (templates)

template <class Gain>
std::size_t FrameRing::read(float* const* out, std::size_t offset, std::size_t frames,
                            Gain&& gain) {
  const std::size_t r = read_.load(std::memory_order_relaxed);
  const std::size_t n = std::min(frames, write_.load(std::memory_order_acquire) - r);
  for (std::size_t i = 0; i < n; ++i) {
    const float g = gain(i);
    const float* f = &data_[((r + i) & mask_) * channels_];
    for (std::size_t c = 0; c < channels_; ++c) out[c][offset + i] = f[c] * g;
  }
  read_.store(r + n, std::memory_order_release);
  return n;
}

template <class Gain>
std::size_t FrameRing::read_interleaved(float* out, std::size_t frames, Gain&& gain) {
  const std::size_t r = read_.load(std::memory_order_relaxed);
  const std::size_t n = std::min(frames, write_.load(std::memory_order_acquire) - r);
  for (std::size_t i = 0; i < n; ++i) {
    const float g = gain(i);
    const float* f = &data_[((r + i) & mask_) * channels_];
    for (std::size_t c = 0; c < channels_; ++c) out[i * channels_ + c] = f[c] * g;
  }
  read_.store(r + n, std::memory_order_release);
  return n;
}

}  // namespace maille::play
