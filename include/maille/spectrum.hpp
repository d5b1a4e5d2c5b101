// Spectra of sampled signals: a radix-2 FFT and peak frequencies estimated between bins. Used
// by the sound tests (a string's fundamental, a drum's partials measured from a WAV file) and
// available to programs.
#pragma once

#include <complex>
#include <cstddef>
#include <span>
#include <vector>

namespace maille::spectrum {

// In-place FFT (forward: exp(-2 pi i k n / N)); the size must be a power of two.
void fft(std::vector<std::complex<double>>& x);

struct Peak {
  double frequency = 0;  // Hz, interpolated between bins
  double magnitude = 0;  // the interpolated peak of |X|, same units as the spectrum
};

// |X(f)| of the Hann-windowed signal, zero-padded to `padding` times its length rounded up to a
// power of two: bin k is at k rate / size. Returns magnitudes for k = 0 .. size / 2.
std::vector<double> magnitude(std::span<const float> x, double rate, int padding, double& bin_hz);

// Local maxima of a magnitude spectrum between f_min and f_max, at least `floor` (relative to
// the largest maximum in the range) and separated by `min_separation` Hz (the larger kept), the
// strongest first. Each peak's frequency is refined by fitting a parabola to the logarithm of
// the three bins around it (exact for a Gaussian, and within a few thousandths of a bin for the
// Hann window's main lobe when padded 4x or more).
std::vector<Peak> peaks(std::span<const double> mag, double bin_hz, double f_min, double f_max,
                        double floor, double min_separation);

// The strongest peak of x between f_min and f_max (Hann window, 8x zero-padding).
Peak dominant(std::span<const float> x, double rate, double f_min, double f_max);

}  // namespace maille::spectrum
