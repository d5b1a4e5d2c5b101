// The viewer's audio path (ring_player.hpp): the ring, the callback that copies from it with a
// smoothed gain, and the producer that keeps it filled.
#include "ring_player.hpp"

#include <bit>
#include <cmath>

#include "play_engine.hpp"

namespace maille::play {

FrameRing::FrameRing(std::size_t channels, std::size_t min_capacity)
    : channels_(channels), mask_(std::bit_ceil(std::max<std::size_t>(min_capacity, 2)) - 1) {
  data_.assign((mask_ + 1) * channels_, 0.0f);
}

std::size_t FrameRing::size() const {
  return write_.load(std::memory_order_acquire) - read_.load(std::memory_order_acquire);
}

std::size_t FrameRing::write(const float* in, std::size_t frames) {
  const std::size_t w = write_.load(std::memory_order_relaxed);
  const std::size_t room = capacity() - (w - read_.load(std::memory_order_acquire));
  const std::size_t n = std::min(frames, room);
  for (std::size_t i = 0; i < n; ++i)
    std::copy(in + i * channels_, in + (i + 1) * channels_, &data_[((w + i) & mask_) * channels_]);
  write_.store(w + n, std::memory_order_release);
  return n;
}

RingPlayer::RingPlayer(std::size_t channels, int rate, std::size_t lead, std::size_t block,
                       float gain)
    : ring_(channels, 4 * lead + 4 * block),
      rate_(rate),
      lead_(lead),
      block_frames_(block),
      block_(block * channels, 0.0f),
      gain_target_(gain),
      gain_(gain),
      ramp_from_(gain),
      ramp_to_(gain),
      ramp_length_(std::max<std::uint32_t>(1, static_cast<std::uint32_t>(kGainRamp * rate))),
      ramp_done_(ramp_length_) {}

// Each sample of a ramp from its start (no sum of steps, whose rounding would gather), exactly
// the target at its end.
float RingPlayer::next_gain() {
  if (ramp_done_ == ramp_length_) return gain_;
  ++ramp_done_;
  gain_ = ramp_done_ == ramp_length_
              ? ramp_to_
              : ramp_from_ + (ramp_to_ - ramp_from_) * (static_cast<float>(ramp_done_) /
                                                        static_cast<float>(ramp_length_));
  return gain_;
}

// A new target starts a ramp from where the gain is (no step: no click).
void RingPlayer::start_period() {
  const float target = gain_target_.load(std::memory_order_relaxed);
  if (target == ramp_to_) return;
  ramp_from_ = gain_;
  ramp_to_ = target;
  ramp_done_ = 0;
}

void RingPlayer::end_period(std::size_t frames, std::size_t got, std::uint64_t clipped) {
  if (got < frames && producing_.load(std::memory_order_acquire))
    underruns_.fetch_add(1, std::memory_order_relaxed);
  if (clipped) clipped_.fetch_add(clipped, std::memory_order_relaxed);
  frames_played_.fetch_add(frames, std::memory_order_relaxed);
}

void RingPlayer::process(float* const* out, std::size_t frames) {
  start_period();
  const std::size_t got = ring_.read(out, 0, frames, [this](std::size_t) { return next_gain(); });
  std::uint64_t clipped = 0;
  for (std::size_t c = 0; c < ring_.channels(); ++c) {
    for (std::size_t i = 0; i < got; ++i) clipped += std::abs(out[c][i]) > 1.0f;
    std::fill(out[c] + got, out[c] + frames, 0.0f);  // what the ring lacked: silence
  }
  end_period(frames, got, clipped);
}

void RingPlayer::process_interleaved(float* out, std::size_t frames) {
  start_period();
  const std::size_t n = ring_.channels();
  const std::size_t got =
      ring_.read_interleaved(out, frames, [this](std::size_t) { return next_gain(); });
  std::uint64_t clipped = 0;
  for (std::size_t i = 0; i < got * n; ++i) clipped += std::abs(out[i]) > 1.0f;
  std::fill(out + got * n, out + frames * n, 0.0f);
  end_period(frames, got, clipped);
}

std::size_t RingPlayer::fill(audio::LiveSource& source, ControlRings* controls, double budget) {
  std::size_t rendered = 0;
  const double start = wall_seconds();
  // The ring holds 4 leads and 4 blocks: a block always fits below the lead.
  while (ring_.size() < lead_ && !source.blown_up() && wall_seconds() - start < budget) {
    if (controls) controls->drain(source);
    const double t0 = thread_cpu_seconds();
    source.render(block_.data(), block_frames_);
    const double cpu = thread_cpu_seconds() - t0;
    ring_.write(block_.data(), block_frames_);
    rendered += block_frames_;
    cpu_seconds_.fetch_add(cpu, std::memory_order_relaxed);
    const double fraction = cpu * rate_ / double(block_frames_);
    double worst = worst_block_.load(std::memory_order_relaxed);
    while (fraction > worst && !worst_block_.compare_exchange_weak(worst, fraction)) {
    }
  }
  rendered_.fetch_add(rendered, std::memory_order_relaxed);
  return rendered;
}

double RingPlayer::seconds_of_slack() const {
  const std::size_t have = ring_.size();
  return have > lead_ / 2 ? double(have - lead_ / 2) / rate_ : 0.0;
}

RingPlayer::Counters RingPlayer::counters(bool take_worst) {
  Counters c;
  c.frames_played = frames_played_.load(std::memory_order_relaxed);
  c.underruns = underruns_.load(std::memory_order_relaxed);
  c.driver_xruns = driver_xruns_.load(std::memory_order_relaxed);
  c.clipped = clipped_.load(std::memory_order_relaxed);
  c.rendered = rendered_.load(std::memory_order_relaxed);
  c.cpu_seconds = cpu_seconds_.load(std::memory_order_relaxed);
  c.worst_block = take_worst ? worst_block_.exchange(0.0) : worst_block_.load();
  return c;
}

}  // namespace maille::play
