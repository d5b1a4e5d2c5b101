// Sound's parts alone: the WAV format byte by byte and back, the sampling plan, the resamplers
// against analytic signals, the FFT's peaks, and the scene keys with --set.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <numbers>
#include <vector>

#include "maille/audio.hpp"
#include "maille/scene.hpp"
#include "maille/spectrum.hpp"
#include "maille/wav.hpp"

namespace maille {
namespace {

constexpr double pi = std::numbers::pi;

std::filesystem::path temp(const std::string& name) {
  return std::filesystem::temp_directory_path() / ("maille_audio_" + name);
}

std::vector<unsigned char> bytes_of(const std::filesystem::path& p) {
  std::ifstream in(p, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

std::uint32_t u32(const std::vector<unsigned char>& b, std::size_t at) {
  return b[at] | b[at + 1] << 8 | b[at + 2] << 16 | std::uint32_t(b[at + 3]) << 24;
}
std::uint32_t u16(const std::vector<unsigned char>& b, std::size_t at) {
  return b[at] | b[at + 1] << 8;
}

TEST(audio, WavPcm16HeaderAndRoundTrip) {
  const std::vector<std::vector<float>> ch{{0.0f, 0.5f, -0.5f, 1.0f, -2.0f},
                                           {1e-3f, -1e-3f, 0.25f, 0.0f, 0.1f}};
  const auto path = temp("pcm16.wav");
  const WavReport r = write_wav(path, ch, 48000, audio::SampleFormat::pcm16, {1.0, 4.0});
  EXPECT_EQ(r.frames, 5u);
  EXPECT_EQ(r.clipped, 1u);  // -2 on channel 0
  EXPECT_DOUBLE_EQ(r.peak[0], 2.0);
  const auto b = bytes_of(path);
  ASSERT_EQ(b.size(), 44u + 5 * 2 * 2);
  EXPECT_EQ(std::string(b.begin(), b.begin() + 4), "RIFF");
  EXPECT_EQ(u32(b, 4), b.size() - 8);
  EXPECT_EQ(std::string(b.begin() + 8, b.begin() + 16), "WAVEfmt ");
  EXPECT_EQ(u32(b, 16), 16u);     // fmt size
  EXPECT_EQ(u16(b, 20), 1u);      // PCM
  EXPECT_EQ(u16(b, 22), 2u);      // channels
  EXPECT_EQ(u32(b, 24), 48000u);  // rate
  EXPECT_EQ(u32(b, 28), 48000u * 4);
  EXPECT_EQ(u16(b, 32), 4u);   // block align
  EXPECT_EQ(u16(b, 34), 16u);  // bits
  EXPECT_EQ(std::string(b.begin() + 36, b.begin() + 40), "data");
  EXPECT_EQ(u32(b, 40), 20u);
  EXPECT_EQ(std::int16_t(u16(b, 44 + 4)), 16384);  // frame 1, channel 0: 0.5 -> round(16383.5)
  const WavData w = read_wav(path);
  EXPECT_EQ(w.rate, 48000);
  EXPECT_EQ(w.format, audio::SampleFormat::pcm16);
  ASSERT_EQ(w.channels.size(), 2u);
  for (std::size_t c = 0; c < 2; ++c)
    for (std::size_t i = 0; i < 5; ++i) {
      const double want = std::clamp(double(ch[c][i]) * (c ? 4.0 : 1.0), -1.0, 1.0);
      EXPECT_NEAR(w.channels[c][i], want, 0.5 / 32767 + 1e-7) << c << " " << i;
    }
  std::filesystem::remove(path);
}

TEST(audio, WavFloat32RoundTripIsExact) {
  std::vector<std::vector<float>> ch(3, std::vector<float>(1000));
  for (std::size_t i = 0; i < 1000; ++i)
    for (std::size_t c = 0; c < 3; ++c)
      ch[c][i] = float(std::sin(0.01 * double(i) * double(c + 1)) * 3.5);
  const auto path = temp("float.wav");
  const WavReport r = write_wav(path, ch, 96000, audio::SampleFormat::float32, {1, 1, 1});
  EXPECT_EQ(r.clipped, 0u);  // float is never clipped
  const auto b = bytes_of(path);
  EXPECT_EQ(u16(b, 20), 3u);  // IEEE float
  EXPECT_EQ(u16(b, 34), 32u);
  EXPECT_EQ(std::string(b.begin() + 38, b.begin() + 42), "fact");
  const WavData w = read_wav(path);
  EXPECT_EQ(w.format, audio::SampleFormat::float32);
  EXPECT_EQ(w.rate, 96000);
  EXPECT_EQ(w.channels, ch);
  std::filesystem::remove(path);
}

TEST(audio, WavErrorsAreReported) {
  EXPECT_THROW(
      write_wav(temp("x.wav"), {{1.0f}, {1.0f, 2.0f}}, 44100, audio::SampleFormat::pcm16, {1, 1}),
      std::invalid_argument);
  // An unwritable place: the error names the file; nothing is left.
  EXPECT_THROW(
      write_wav("/proc/maille_no/x.wav", {{1.0f}}, 44100, audio::SampleFormat::pcm16, {1.0}),
      std::runtime_error);
  const auto path = temp("not.wav");
  std::ofstream(path) << "RIFF....WAVEjunk";
  EXPECT_THROW(read_wav(path), std::runtime_error);
  std::filesystem::remove(path);
}

TEST(audio, SamplingPlanIsExactOnlyForWholeFractions) {
  EXPECT_TRUE(audio::plan_sampling(1.0 / 44100, 44100, audio::Resampler::sinc).exact);
  const auto two = audio::plan_sampling(1.0 / 88200, 44100, audio::Resampler::sinc);
  EXPECT_TRUE(two.exact);
  EXPECT_EQ(two.steps_per_sample, 2u);
  EXPECT_TRUE(audio::plan_sampling(2.2675736961451248e-05, 44100, audio::Resampler::sinc).exact);
  EXPECT_FALSE(audio::plan_sampling(1e-5, 44100, audio::Resampler::sinc).exact);
  EXPECT_FALSE(audio::plan_sampling(1e-4, 44100, audio::Resampler::sinc).exact);  // > 1/rate
  EXPECT_FALSE(audio::plan_sampling(2.27e-05, 44100, audio::Resampler::sinc).exact);
}

// A sum of sinusoids sampled at n h, resampled to k / rate, against its exact values there.
double resampling_error(double h, int rate, audio::Resampler kind, double edge) {
  const double f[] = {440, 3000, 9000};
  auto signal = [&](double t) {
    return std::sin(2 * pi * f[0] * t) + 0.5 * std::cos(2 * pi * f[1] * t + 0.3) +
           0.25 * std::sin(2 * pi * f[2] * t + 1);
  };
  audio::StreamResampler r(h, rate, kind);
  const double seconds = 0.05;
  for (double n = 0; n * h <= seconds; n += 1) r.push(signal(n * h));
  r.finish();
  double worst = 0;
  for (std::size_t k = 0; k < r.out().size(); ++k) {
    const double t = double(k) / rate;
    if (t < edge || t > seconds - edge) continue;
    worst = std::max(worst, std::abs(r.out()[k] - signal(t)));
  }
  return worst;
}

TEST(audio, SincResamplerIsBandLimitedAndAccurate) {
  const double edge = 0.001;  // the kernel is cut at the signal's ends
  // Down (h = 1e-5 to 44100 Hz) and up (h = 1e-4, below the audio rate: 9 kHz is beyond its
  // band, so only the two lower tones there).
  EXPECT_LT(resampling_error(1e-5, 44100, audio::Resampler::sinc, edge), 2e-4);
  EXPECT_LT(resampling_error(1.0 / 30000, 48000, audio::Resampler::sinc, edge), 2e-4);
  // Linear: within (pi f h)^2 / 2 per tone, summed with the amplitudes (1, 0.5, 0.25).
  const double h = 1e-5, bound = std::pow(pi * h, 2) / 2 * (440 * 440 + 0.5 * 9e6 + 0.25 * 81e6);
  const double linear = resampling_error(h, 44100, audio::Resampler::linear, 0);
  EXPECT_LT(linear, bound);
  EXPECT_GT(linear, 0.1 * bound);
  // A tone above the output's Nyquist frequency is removed by the sinc path, not aliased.
  audio::StreamResampler r(1e-5, 44100, audio::Resampler::sinc);
  for (int n = 0; n <= 5000; ++n) r.push(std::sin(2 * pi * 30000 * n * 1e-5));
  r.finish();
  double level = 0;
  for (std::size_t k = 100; k + 100 < r.out().size(); ++k)
    level = std::max(level, double(std::abs(r.out()[k])));
  EXPECT_LT(level, 1e-3);
}

TEST(audio, FftPeakIsFoundBetweenBins) {
  const double rate = 8000, f = 441.37;
  std::vector<float> x(4000);
  for (std::size_t i = 0; i < x.size(); ++i) x[i] = float(std::sin(2 * pi * f * double(i) / rate));
  const spectrum::Peak p = spectrum::dominant(x, rate, 100, 1000);
  EXPECT_LT(std::abs(p.frequency - f), 0.01);  // a bin is 2 Hz before padding
  // The FFT of a delta is flat; of a constant, a delta.
  std::vector<std::complex<double>> d(16);
  d[0] = 1;
  spectrum::fft(d);
  for (const auto& c : d) EXPECT_NEAR(std::abs(c - 1.0), 0, 1e-12);
  EXPECT_THROW(
      [] {
        std::vector<std::complex<double>> odd(12);
        spectrum::fft(odd);
      }(),
      std::invalid_argument);
}

const char* kScene = R"(
[[rope]]
name = "string"
points = 10
[[listen]]
group = "string"
index = 3
quantity = "position"
axis = [0.0, 0.0, 2.0]
[[listen]]
point = "string:4"
[audio]
rate = 48000
format = "float32"
gain = 10
resampler = "linear"
)";

TEST(audio, SceneKeysAreReadAndOverridable) {
  const auto kinds = LinkKindRegistry::with_builtins();
  const auto stages = StageRegistry::with_builtins();
  auto s = parse_scene(kScene, "s.toml", kinds, stages);
  ASSERT_TRUE(s.ok()) << s.error().to_string();
  ASSERT_EQ(s->audio.listeners.size(), 2u);
  const Group* g = s->model.group("string");
  EXPECT_EQ(s->audio.listeners[0].point, g->first + 3);
  EXPECT_EQ(s->audio.listeners[0].quantity, audio::Quantity::position);
  EXPECT_EQ(s->audio.listeners[0].axis.z, 1);  // normalised
  EXPECT_EQ(s->audio.listeners[1].point, g->first + 4);
  EXPECT_EQ(s->audio.listeners[1].quantity, audio::Quantity::velocity);  // the default
  EXPECT_EQ(s->audio.listeners[1].axis.y, 1);                            // the default
  EXPECT_EQ(s->audio.settings.rate, 48000);
  EXPECT_EQ(s->audio.settings.format, audio::SampleFormat::float32);
  EXPECT_EQ(s->audio.settings.gain, 10);
  EXPECT_EQ(s->audio.settings.resampler, audio::Resampler::linear);

  const std::vector<std::string> sets{"listen[1].quantity=force", "audio.rate=22050",
                                      "audio.gain=auto"};
  auto o = parse_scene(kScene, "s.toml", kinds, stages, sets);
  ASSERT_TRUE(o.ok()) << o.error().to_string();
  EXPECT_EQ(o->audio.listeners[1].quantity, audio::Quantity::force);
  EXPECT_EQ(o->audio.settings.rate, 22050);
  EXPECT_EQ(o->audio.settings.gain, 0);

  const std::vector<std::string> bad{"audio.rate=999999"};
  auto e = parse_scene(kScene, "s.toml", kinds, stages, bad);
  ASSERT_FALSE(e.ok());
  EXPECT_EQ(e.error().key, "audio.rate");
  EXPECT_NE(e.error().to_string().find("(--set)"), std::string::npos) << e.error().to_string();

  const std::vector<std::string> added{"listen[0].axis=[0,0,0]"};
  auto z = parse_scene(kScene, "s.toml", kinds, stages, added);
  ASSERT_FALSE(z.ok());
  EXPECT_EQ(z.error().key, "listen[0].axis");

  // A scene without [[listen]] is silent: no channel, nothing to refuse.
  auto quiet = parse_scene("[[mass]]\nposition = [0.0, 0.0, 0.0]\n", "q.toml", kinds, stages);
  ASSERT_TRUE(quiet.ok());
  EXPECT_TRUE(quiet->audio.listeners.empty());
}

}  // namespace
}  // namespace maille
