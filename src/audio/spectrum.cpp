// Spectra: an iterative radix-2 FFT, a Hann-windowed zero-padded magnitude spectrum, and peaks
// refined by a parabola through the log magnitudes of three bins.
#include "maille/spectrum.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>

namespace maille::spectrum {

void fft(std::vector<std::complex<double>>& x) {
  const std::size_t n = x.size();
  if (n == 0 || (n & (n - 1)) != 0) throw std::invalid_argument("fft: size must be a power of 2");
  for (std::size_t i = 1, j = 0; i < n; ++i) {  // bit reversal
    std::size_t bit = n >> 1;
    for (; j & bit; bit >>= 1) j ^= bit;
    j ^= bit;
    if (i < j) std::swap(x[i], x[j]);
  }
  for (std::size_t len = 2; len <= n; len <<= 1) {
    const double angle = -2 * std::numbers::pi / double(len);
    for (std::size_t i = 0; i < n; i += len)
      for (std::size_t k = 0; k < len / 2; ++k) {
        // Twiddles computed directly (not by repeated multiplication): no accumulated error.
        const std::complex<double> w = std::polar(1.0, angle * double(k));
        const std::complex<double> a = x[i + k], b = x[i + k + len / 2] * w;
        x[i + k] = a + b;
        x[i + k + len / 2] = a - b;
      }
  }
}

std::vector<double> magnitude(std::span<const float> x, double rate, int padding, double& bin_hz) {
  std::size_t size = 1;
  while (size < x.size() * std::size_t(std::max(padding, 1))) size <<= 1;
  std::vector<std::complex<double>> buf(size);
  const double n = double(x.size());
  for (std::size_t i = 0; i < x.size(); ++i) {
    const double w = 0.5 - 0.5 * std::cos(2 * std::numbers::pi * (double(i) + 0.5) / n);
    buf[i] = double(x[i]) * w;
  }
  fft(buf);
  bin_hz = rate / double(size);
  std::vector<double> mag(size / 2 + 1);
  for (std::size_t k = 0; k < mag.size(); ++k) mag[k] = std::abs(buf[k]);
  return mag;
}

std::vector<Peak> peaks(std::span<const double> mag, double bin_hz, double f_min, double f_max,
                        double floor, double min_separation) {
  std::vector<Peak> found;
  const std::size_t lo = std::max<std::size_t>(1, std::size_t(std::ceil(f_min / bin_hz)));
  const std::size_t hi = std::min(mag.size() - 2, std::size_t(std::floor(f_max / bin_hz)));
  for (std::size_t k = lo; k <= hi; ++k) {
    if (!(mag[k] > mag[k - 1] && mag[k] >= mag[k + 1])) continue;
    const double a = std::log(std::max(mag[k - 1], 1e-300)), b = std::log(mag[k]),
                 c = std::log(std::max(mag[k + 1], 1e-300));
    const double denom = a - 2 * b + c;
    const double delta = denom < 0 ? 0.5 * (a - c) / denom : 0.0;  // in (-0.5, 0.5)
    found.push_back({(double(k) + delta) * bin_hz, std::exp(b - 0.25 * (a - c) * delta)});
  }
  std::sort(found.begin(), found.end(),
            [](const Peak& p, const Peak& q) { return p.magnitude > q.magnitude; });
  std::vector<Peak> kept;
  const double level = found.empty() ? 0 : found.front().magnitude * floor;
  for (const Peak& p : found) {
    if (p.magnitude < level) break;
    const bool close = std::any_of(kept.begin(), kept.end(), [&](const Peak& q) {
      return std::abs(q.frequency - p.frequency) < min_separation;
    });
    if (!close) kept.push_back(p);
  }
  return kept;
}

Peak dominant(std::span<const float> x, double rate, double f_min, double f_max) {
  double bin = 0;
  const std::vector<double> mag = magnitude(x, rate, 8, bin);
  const std::vector<Peak> p = peaks(mag, bin, f_min, f_max, 0, 0);
  return p.empty() ? Peak{} : p.front();
}

}  // namespace maille::spectrum
