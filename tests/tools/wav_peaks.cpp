// wav_peaks FILE [--channel C] [--from T0] [--to T1] [--min F] [--max F] [--count N]
//           [--expect F --tolerance R]
// Prints the strongest spectral peaks of one channel of a WAV file (Hann window, 8x zero
// padding, peaks refined between bins), strongest first. With --expect, exits 1 unless the
// strongest peak is within the relative tolerance of F (the CLI sound tests).
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <exception>
#include <string>

#include "maille/spectrum.hpp"
#include "maille/wav.hpp"

int main(int argc, char** argv) {
  if (argc < 2) {
    std::fprintf(stderr,
                 "usage: wav_peaks FILE [--channel C] [--from T0] [--to T1] [--min F] "
                 "[--max F] [--count N] [--expect F --tolerance R]\n");
    return 2;
  }
  std::size_t channel = 0, count = 8;
  double from = 0, to = 1e300, fmin = 20, fmax = 20000, expect = 0, tolerance = 0.005;
  for (int i = 2; i + 1 < argc; i += 2) {
    const std::string k = argv[i];
    const double v = std::atof(argv[i + 1]);
    if (k == "--channel")
      channel = std::size_t(v);
    else if (k == "--from")
      from = v;
    else if (k == "--to")
      to = v;
    else if (k == "--min")
      fmin = v;
    else if (k == "--max")
      fmax = v;
    else if (k == "--count")
      count = std::size_t(v);
    else if (k == "--expect")
      expect = v;
    else if (k == "--tolerance")
      tolerance = v;
    else {
      std::fprintf(stderr, "unknown option %s\n", k.c_str());
      return 2;
    }
  }
  try {
    const maille::WavData w = maille::read_wav(argv[1]);
    if (channel >= w.channels.size()) {
      std::fprintf(stderr, "%s has %zu channels\n", argv[1], w.channels.size());
      return 2;
    }
    const auto& x = w.channels[channel];
    const std::size_t a = std::min(x.size(), std::size_t(from * w.rate));
    const std::size_t b = std::min(x.size(), std::size_t(std::min(to * w.rate, 1e15)));
    double bin = 0;
    const auto mag = maille::spectrum::magnitude({x.data() + a, b - a}, w.rate, 8, bin);
    const auto peaks = maille::spectrum::peaks(mag, bin, fmin, fmax, 1e-3, 2 * bin * 8);
    std::printf("%s: channel %zu of %zu, %d Hz, samples %zu..%zu\n", argv[1], channel,
                w.channels.size(), w.rate, a, b);
    for (std::size_t i = 0; i < peaks.size() && i < count; ++i)
      std::printf("  %10.4f Hz  %8.2f dB\n", peaks[i].frequency,
                  20 * std::log10(peaks[i].magnitude / peaks[0].magnitude));
    if (expect > 0) {
      const double f = peaks.empty() ? 0 : peaks[0].frequency;
      const double err = std::abs(f - expect) / expect;
      std::printf("strongest %.4f Hz, expected %.4f Hz: relative error %.2e (tolerance %.1e)\n", f,
                  expect, err, tolerance);
      return err <= tolerance ? 0 : 1;
    }
  } catch (const std::exception& e) {
    std::fprintf(stderr, "error: %s\n", e.what());
    return 1;
  }
  return 0;
}
