// Streaming resamplers: samples at n h (the simulation's steps) to samples at k / rate.
//
// Band-limited (sinc): each output is a weighted sum of the inputs within +-T of its time,
//
//   y(t) = sum_n x_n g(t - n h) / sum_n g(t - n h),   g(tau) = sinc(2 fc tau) w(tau / T),
//
// with fc = 0.45 min(rate, 1/h) (below both Nyquist frequencies), T = 16 / (2 fc) (16 zero
// crossings each side) and w the Blackman window. Dividing by the sum of the weights keeps a
// constant signal exact whatever the ratio of the rates, and renormalises the truncated kernel
// at the end of the signal. The kernel is tabulated once (256 points per zero crossing, linear
// in between: relative error ~1e-5 of a tap) so that a sample costs one multiply-add per tap.
#include <algorithm>
#include <cmath>
#include <numbers>
#include <vector>

#include "maille/audio.hpp"

namespace maille::audio {

namespace {

constexpr int kZeroCrossings = 16;
constexpr int kTablePerCrossing = 256;
constexpr double kCutoff = 0.45;  // of min(rate, 1/h)

// g(u) for u = j / kTablePerCrossing, j = 0 .. kZeroCrossings * kTablePerCrossing (+1 guard).
const std::vector<double>& kernel_table() {
  static const std::vector<double> table = [] {
    constexpr double pi = std::numbers::pi;
    std::vector<double> g(kZeroCrossings * kTablePerCrossing + 2, 0.0);
    for (std::size_t j = 0; j + 1 < g.size(); ++j) {
      const double u = double(j) / kTablePerCrossing;
      const double r = u / kZeroCrossings;  // window position in [0, 1]
      const double sinc = j == 0 ? 1.0 : std::sin(pi * u) / (pi * u);
      const double window = 0.42 + 0.5 * std::cos(pi * r) + 0.08 * std::cos(2 * pi * r);
      g[j] = r <= 1 ? sinc * window : 0.0;
    }
    return g;
  }();
  return table;
}

double kernel(double u) {
  const double a = std::abs(u) * kTablePerCrossing;
  const auto j = static_cast<std::size_t>(a);
  const auto& g = kernel_table();
  if (j + 1 >= g.size()) return 0.0;
  const double frac = a - double(j);
  return g[j] + (g[j + 1] - g[j]) * frac;
}

}  // namespace

StreamResampler::StreamResampler(double in_step, int out_rate, Resampler kind)
    : h_(in_step), rate_(out_rate), kind_(kind) {
  cutoff_ = kCutoff * std::min(rate_, 1.0 / h_);
  half_width_ = kZeroCrossings / (2 * cutoff_);
}

void StreamResampler::push(double x) {
  in_.push_back(x);
  ++pushed_;
  emit(false);
}

void StreamResampler::finish() {
  emit(true);
}

// The output at time t from the inputs kept (indices first_ on).
double StreamResampler::sample_at(double t) const {
  const double last = double(pushed_ - 1);
  if (kind_ == Resampler::linear) {
    const double u = std::min(t / h_, last);
    const auto n0 = static_cast<std::uint64_t>(std::floor(u));
    const double frac = u - double(n0);
    const double x0 = in_[n0 - first_];
    if (frac <= 0 || n0 + 1 >= pushed_) return x0;
    return x0 + (in_[n0 + 1 - first_] - x0) * frac;
  }
  const double lo = std::max(std::ceil((t - half_width_) / h_), double(first_));
  const double hi = std::min(std::floor((t + half_width_) / h_), last);
  double sum = 0, weights = 0;
  for (double n = lo; n <= hi; n += 1) {
    const double w = kernel(2 * cutoff_ * (t - n * h_));
    sum += w * in_[static_cast<std::size_t>(n) - first_];
    weights += w;
  }
  return weights != 0 ? sum / weights : 0.0;
}

// Produces every output whose inputs have all arrived (final: every output up to the last
// input's time), then drops the inputs no later output needs.
void StreamResampler::emit(bool final) {
  if (pushed_ == 0) return;
  const double t_last = double(pushed_ - 1) * h_;
  const double reach = kind_ == Resampler::sinc ? half_width_ : h_;
  for (;;) {
    const double t = double(emitted_) / rate_;
    if (final ? t > t_last * (1 + 1e-12) : t + reach > t_last) break;
    out_.push_back(static_cast<float>(sample_at(t)));
    ++emitted_;
  }
  const double next = double(emitted_) / rate_;
  const double keep_from = std::floor((next - reach) / h_) - 1;
  if (keep_from > double(first_) + double(in_.size()) / 2 && keep_from > 1024) {
    const auto drop = static_cast<std::uint64_t>(keep_from) - first_;
    in_.erase(in_.begin(), in_.begin() + static_cast<std::ptrdiff_t>(drop));
    first_ += drop;
  }
}

}  // namespace maille::audio
