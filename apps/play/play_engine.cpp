// The audio callback's work in `maille play` (play_engine.hpp): controls, the model's samples,
// the CPU time of each period; the recording's writer thread.
#include "play_engine.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <ctime>

namespace maille::play {

namespace {

double seconds(clockid_t clock) {
  timespec t{};
  clock_gettime(clock, &t);
  return double(t.tv_sec) + 1e-9 * double(t.tv_nsec);
}

}  // namespace

double thread_cpu_seconds() {
  return seconds(CLOCK_THREAD_CPUTIME_ID);
}
double wall_seconds() {
  return seconds(CLOCK_MONOTONIC);
}

PlayEngine::PlayEngine(audio::LiveSource& s, int r, std::size_t max_frames, std::uint64_t limit,
                       bool record)
    : source(s),
      rate(r),
      channels(s.channels()),
      frame_limit(limit),
      block(max_frames * s.channels(), 0.0f) {
  if (record) sent = std::make_unique<audio::SpscRing<float, (1 << 20)>>();
}

void PlayEngine::period_interleaved(float* out, std::size_t frames) {
  const double t0 = thread_cpu_seconds(), w0 = wall_seconds();
  controls.drain(source);
  const std::uint64_t done = frames_played.load(std::memory_order_relaxed);
  std::size_t live = frames;
  if (frame_limit)
    live = static_cast<std::size_t>(
        std::min<std::uint64_t>(frames, frame_limit - std::min(done, frame_limit)));
  if (live) source.render(out, live);
  std::fill(out + live * channels, out + frames * channels, 0.0f);
  if (sent)
    for (std::size_t i = 0; i < live * channels; ++i)
      if (!sent->push(out[i])) record_dropped.fetch_add(1, std::memory_order_relaxed);
  frames_played.store(done + live, std::memory_order_relaxed);
  if ((frame_limit && done + live >= frame_limit) || source.blown_up())
    finished.store(true, std::memory_order_release);
  account(thread_cpu_seconds() - t0, wall_seconds() - w0, frames);
}

// RtAudio may hand a period larger than asked (the block was sized for the period it opened
// with): in pieces of the block's size, each accounted as a period.
void PlayEngine::process_interleaved(float* out, std::size_t frames) {
  const std::size_t per = block.size() / channels;
  for (std::size_t start = 0; start < frames;) {
    const std::size_t n = std::min(frames - start, per);
    period_interleaved(out + start * channels, n);
    start += n;
  }
}

void PlayEngine::process(float* const* out, std::size_t frames) {
  float* b = block.data();
  for (std::size_t start = 0; start < frames;) {  // in pieces of the block's size
    const std::size_t n = std::min(frames - start, block.size() / channels);
    period_interleaved(b, n);
    for (std::size_t c = 0; c < channels; ++c)
      for (std::size_t i = 0; i < n; ++i) out[c][start + i] = b[i * channels + c];
    start += n;
  }
}

void PlayEngine::account(double cpu_s, double wall_s, std::size_t frames) {
  const double period = double(frames) / rate;
  cpu.add(cpu_s / period);
  wall.add(wall_s / period);
}

void Fractions::add(double fraction) {
  max = std::max(max, fraction);
  sum += fraction;
  ++count;
  ++bins[static_cast<std::size_t>(std::clamp(fraction * 200.0, 0.0, double(kBins)))];
}

// The upper edge of the bin (0.5 % of a period) where p of the periods are reached, at most
// the largest.
double Fractions::percentile(double p) const {
  const double want = p * double(count);
  double seen = 0;
  for (int b = 0; b <= kBins; ++b) {
    seen += bins[b];
    if (seen >= want && seen > 0) return std::min((b + 1) / 200.0, max);
  }
  return max;
}

Recording::Recording(PlayEngine& engine) : engine_(engine) {
  interleaved_.reserve(std::size_t(engine.rate) * engine.channels * 60);
  thread_ = std::thread([this] {
    while (!stop_.load()) {
      drain();
      std::this_thread::sleep_for(std::chrono::milliseconds(20));
    }
    drain();
  });
}

Recording::~Recording() {
  if (thread_.joinable()) {
    stop_ = true;
    thread_.join();
  }
}

void Recording::drain() {
  float x;
  while (engine_.sent->pop(x)) interleaved_.push_back(x);
}

std::vector<std::vector<float>> Recording::finish() {
  if (thread_.joinable()) {
    stop_ = true;
    thread_.join();
  }
  const std::size_t n = engine_.channels;
  std::vector<std::vector<float>> out(n);
  for (std::size_t c = 0; c < n; ++c) {
    out[c].reserve(interleaved_.size() / n);
    for (std::size_t i = c; i + n - c <= interleaved_.size(); i += n)
      out[c].push_back(interleaved_[i]);
  }
  return out;
}

}  // namespace maille::play
