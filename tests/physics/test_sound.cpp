// Sound that knows the physics: the examples' WAV files (written and read back) against the
// analytic modes of what they model, and the samples' times checked on an oscillator whose
// leapfrog trajectory is known exactly.
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <numbers>
#include <optional>

#include "maille/audio.hpp"
#include "maille/links/friction.hpp"
#include "maille/scene.hpp"
#include "maille/simulator.hpp"
#include "maille/spectrum.hpp"
#include "maille/wav.hpp"

namespace maille {
namespace {

constexpr double pi = std::numbers::pi;

// Runs examples/NAME.toml for its duration with its listeners, writes the WAV as `maille run
// --audio` does (same writer, same gains), reads it back. `model` receives a copy of the model.
WavData run_example_to_wav(const std::string& name, Model* model = nullptr) {
  auto scene = load_scene(std::string(MAILLE_SOURCE_DIR "/examples/") + name + ".toml");
  EXPECT_TRUE(scene.ok()) << scene.error().to_string();
  if (model) *model = scene->model;
  SimulationSettings settings = scene->settings;
  settings.threads = 1;
  Simulator sim(std::move(scene->model), settings);
  audio::Recorder recorder(scene->audio, settings.step);
  recorder.attach(sim);
  const auto steps = static_cast<std::uint64_t>(std::llround(settings.duration / settings.step));
  EXPECT_TRUE(sim.run_steps(steps));
  EXPECT_TRUE(sim.check_energy());  // the end-of-run pass, as `maille run` makes it
  recorder.finish();
  const auto path = std::filesystem::temp_directory_path() / ("maille_test_" + name + ".wav");
  write_wav(path, recorder.channels(), scene->audio.settings.rate, scene->audio.settings.format,
            audio::output_gains(recorder.channels(), scene->audio));
  WavData w = read_wav(path);
  std::filesystem::remove(path);
  return w;
}

std::span<const float> from(const std::vector<float>& x, double seconds, int rate) {
  const auto a = std::min(x.size(), static_cast<std::size_t>(seconds * rate));
  return {x.data() + a, x.size() - a};
}

// The plucked string: N beads of mass m, spacing a, tension T between fixed ends. Its modes
// (the study's string mode, `maille study validity`) are
//   omega_n = 2 sqrt(T / (m a)) sin(n pi / (2 (N + 1))),
// and leapfrog at step h plays omega_n' = (2 / h) asin(omega_n h / 2) (its exact dispersion).
TEST(sound, PluckedStringFundamentalFromTheWavMatchesTheDiscreteMode) {
  Model m;
  const WavData w = run_example_to_wav("sound_plucked_string", &m);
  ASSERT_EQ(w.rate, 44100);
  ASSERT_EQ(w.channels.size(), 2u);
  const Group* g = m.group("string");
  ASSERT_NE(g, nullptr);
  const auto* springs = m.links.find("spring_damper");
  ASSERT_NE(springs, nullptr);
  const double a =
      norm(m.points.initial_position[g->first + 1] - m.points.initial_position[g->first]);
  const double tension = springs->param(0, 0) * (a - springs->param(0, 1));  // k (a - L0)
  const double bead = m.points.mass[g->first + 1];
  const int n_beads = static_cast<int>(g->count) - 2;
  const double h = 1.0 / 44100;
  for (int n = 1; n <= 3; ++n) {
    const double omega =
        2 * std::sqrt(tension / (bead * a)) * std::sin(n * pi / (2 * (n_beads + 1)));
    const double f = std::asin(omega * h / 2) * 2 / h / (2 * pi);
    // Channel 1 (the bridge force) has the fundamental strongest; look around each partial.
    const spectrum::Peak p =
        spectrum::dominant(from(w.channels[1], 0.05, w.rate), w.rate, f * 0.95, f * 1.05);
    const double err = std::abs(p.frequency - f) / f;
    std::printf("string partial %d: analytic %.4f Hz, measured %.4f Hz, error %.2e\n", n, f,
                p.frequency, err);
    EXPECT_LT(err, 0.005) << "partial " << n;
    if (n == 1) {  // and the strongest peak of the bridge force below 400 Hz is the fundamental
      const spectrum::Peak top =
          spectrum::dominant(from(w.channels[1], 0.05, w.rate), w.rate, 50, 400);
      EXPECT_LT(std::abs(top.frequency - f) / f, 0.005);
    }
  }
}

// The membrane's transverse modes. Continuum: the zeros j_mn of the Bessel functions,
// f_mn / f_01 = j_mn / j_01. The lattice itself: with pretension every link of built length L
// and rest length L0 pulls with T = k (L - L0), so a transverse displacement u sees the
// stiffness matrix K = sum over links of T / L (u_i - u_j)^2 terms on the free points, and its
// modes are the eigenvalues of M^-1 K (the model's exact small-amplitude modes).
TEST(sound, DrumPartialsKeepTheBesselRatiosAndTheLatticeModes) {
  Model m;
  const WavData w = run_example_to_wav("sound_drum", &m);
  ASSERT_EQ(w.channels.size(), 1u);
  double bin = 0;
  const auto mag = spectrum::magnitude(from(w.channels[0], 0.05, w.rate), w.rate, 8, bin);
  const auto peaks = spectrum::peaks(mag, bin, 50, 2000, 1e-3, 4.0);
  ASSERT_FALSE(peaks.empty());
  // The fundamental: the strongest peak below 250 Hz.
  double f01 = 0;
  for (const auto& p : peaks)
    if (p.frequency < 250) {
      f01 = p.frequency;
      break;
    }
  ASSERT_GT(f01, 0);
  // The nearest peak within -40 dB of the strongest to each predicted frequency.
  auto nearest = [&](double f) {
    double best = 0;
    for (const auto& p : peaks)
      if (p.magnitude > peaks.front().magnitude * 1e-2 &&
          std::abs(p.frequency - f) < std::abs(best - f))
        best = p.frequency;
    return best;
  };
  // j_01, j_11, j_21, j_02, j_31, j_12
  const double j[] = {2.404825557695773, 3.831705970207512, 5.135622301840683,
                      5.520078110286311, 6.380161895923984, 7.015586669815619};
  for (int i = 1; i < 6; ++i) {
    const double ratio = j[i] / j[0];
    const double f = nearest(ratio * f01);
    const double err = std::abs(f / f01 - ratio) / ratio;
    std::printf("drum partial %d: Bessel ratio %.4f, measured %.4f (%.3f Hz), error %.2e\n", i,
                ratio, f / f01, f, err);
    EXPECT_LT(err, 0.02) << "partial with ratio " << ratio;
  }

  // The lattice's own modes: M^-1 K on the free points of the skin (equal masses).
  const Group* skin = m.group("skin");
  ASSERT_NE(skin, nullptr);
  std::vector<int> row(m.points.size(), -1);
  int n = 0;
  for (std::uint32_t i = skin->first; i < skin->first + skin->count; ++i)
    if (m.points.inv_mass[i] > 0) row[i] = n++;
  Eigen::MatrixXd k = Eigen::MatrixXd::Zero(n, n);
  const auto* springs = m.links.find("spring_damper");
  for (std::size_t id = 0; id < springs->size(); ++id) {
    const LinkEnds e = springs->ends(id);
    const double length = norm(m.points.initial_position[e.b] - m.points.initial_position[e.a]);
    const double t_over_l = springs->param(id, 0) * (length - springs->param(id, 1)) / length;
    for (const auto& [p, q] : {std::pair{e.a, e.b}, std::pair{e.b, e.a}})
      if (row[p] >= 0) {
        k(row[p], row[p]) += t_over_l;
        if (row[q] >= 0) k(row[p], row[q]) -= t_over_l;
      }
  }
  const double bead = m.points.mass[skin->first + skin->count / 2];
  Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> modes(k / bead, Eigen::EigenvaluesOnly);
  const double h = 1.0 / 44100;
  std::vector<double> lattice;
  for (int i = 0; i < n; ++i) {
    const double omega = std::sqrt(modes.eigenvalues()[i]);
    lattice.push_back(std::asin(omega * h / 2) * 2 / h / (2 * pi));  // leapfrog's dispersion
  }
  std::printf("lattice modes:");
  for (int i = 0; i < 12; ++i) std::printf(" %.3f", lattice[std::size_t(i)]);
  std::printf(" Hz\n");
  EXPECT_LT(std::abs(f01 - lattice[0]) / lattice[0], 0.002);
  for (int i = 1; i < 6; ++i) {
    const double f = nearest(j[i] / j[0] * f01);
    double closest = lattice[0];
    for (const double l : lattice)
      if (std::abs(l - f) < std::abs(closest - f)) closest = l;
    std::printf("drum partial %.3f Hz: nearest lattice mode %.3f Hz, error %.2e\n", f, closest,
                std::abs(f - closest) / closest);
    EXPECT_LT(std::abs(f - closest) / closest, 0.002);
  }
}

// One mass on a spring under leapfrog, released from x0 = A at rest: its discrete trajectory is
// exactly x_n = A cos(w' n h) with sin(w' h / 2) = w h / 2, its synchronised velocity
// (x_n+1 - x_n-1) / 2h = -A sin(w' h) / h sin(w' n h), the force on its anchor k x_n. Sample k of
// each channel must be those at t = k / rate: exactly when h = 1 / (K rate), within the resampler's
// error otherwise.
struct Oscillator {
  static constexpr double k = 1000, m = 1000 / (2 * pi * 440) / (2 * pi * 440), A = 1e-3;
  static std::string scene(double step, const char* resampler) {
    char text[1600];
    std::snprintf(text, sizeof text, R"(
[simulation]
step = %.17g
[fields]
gravity = [0.0, 0.0, 0.0]
[[fixed]]
name = "anchor"
position = [0.0, 0.0, 0.0]
[[mass]]
name = "bob"
position = [1.001, 0.0, 0.0]
mass = %.17g
[[link]]
kind = "spring"
a = "anchor"
b = "bob"
stiffness = 1000.0
rest_length = 1.0
[[listen]]
point = "bob"
quantity = "position"
axis = [1.0, 0.0, 0.0]
[[listen]]
point = "bob"
quantity = "velocity"
axis = [1.0, 0.0, 0.0]
[[listen]]
point = 1
quantity = "force"
axis = [2.0, 0.0, 0.0]
[audio]
rate = 44100
resampler = "%s"
)",
                  step, m, resampler);
    return text;
  }
  // Channels for `seconds` of simulation, and the largest error of each against the exact
  // discrete solution, relative to each channel's amplitude.
  static std::array<double, 3> errors(double step, const char* resampler, double seconds,
                                      bool force_resample = false) {
    auto scene = parse_scene(Oscillator::scene(step, resampler), "oscillator.toml",
                             LinkKindRegistry::with_builtins());
    EXPECT_TRUE(scene.ok()) << scene.error().to_string();
    Simulator sim(std::move(scene->model), scene->settings);
    audio::Recorder rec(scene->audio, step, force_resample);
    rec.attach(sim);
    sim.run_steps(static_cast<std::uint64_t>(std::llround(seconds / step)));
    sim.check_energy();
    rec.finish();
    const double w = 2 * pi * 440, wd = 2 * std::asin(w * step / 2) / step;
    const double vamp = A * std::sin(wd * step) / step;
    std::array<double, 3> worst{};
    const auto& ch = rec.channels();
    EXPECT_EQ(ch[0].size(), static_cast<std::size_t>(std::floor(seconds * 44100 + 1e-6)) + 1);
    // The windowed sinc's kernel is cut at both ends of the signal (nothing before t = 0 or
    // after the last step): those 16 / (2 fc) seconds are left out of its comparison.
    const bool sinc = !rec.plan().exact && rec.plan().resampler == audio::Resampler::sinc;
    const double edge = sinc ? 16 / (2 * 0.45 * std::min(44100.0, 1 / step)) : 0.0;
    for (std::size_t i = 0; i < ch[0].size(); ++i) {
      const double t = double(i) / 44100;
      if (t < edge || t > seconds - edge) continue;
      // position: displacement from the initial position; force: on the anchor (point 1, the
      // [[fixed]] after the [[mass]]), the spring's reaction +k x.
      worst[0] = std::max(worst[0], std::abs(ch[0][i] - A * (std::cos(wd * t) - 1)) / A);
      worst[1] = std::max(worst[1], std::abs(ch[1][i] + vamp * std::sin(wd * t)) / vamp);
      worst[2] = std::max(worst[2], std::abs(ch[2][i] - k * A * std::cos(wd * t)) / (k * A));
    }
    return worst;
  }
};

TEST(sound, ExactSamplingReadsTheStateAtEachSampleTime) {
  for (const int per_sample : {1, 2, 3}) {
    const auto e = Oscillator::errors(1.0 / (44100.0 * per_sample), "sinc", 0.05);
    std::printf("exact, %d steps per sample: errors position %.2e velocity %.2e force %.2e\n",
                per_sample, e[0], e[1], e[2]);
    for (const double x : e)
      EXPECT_LT(x, 2e-6);  // float samples; an unsynchronised
                           // velocity would be off by w h / 2 ~ 3e-2
  }
}

TEST(sound, ResamplingMatchesTheExactPath) {
  // The same run (h = 1 / 88200) through the exact path and forced through each resampler.
  const double h = 1.0 / 88200;
  const auto exact = Oscillator::errors(h, "sinc", 0.05);
  const auto sinc = Oscillator::errors(h, "sinc", 0.05, true);
  const auto linear = Oscillator::errors(h, "linear", 0.05, true);
  // A step that is no fraction of 1 / 44100: the resampled path only.
  const auto sinc_odd = Oscillator::errors(1e-5, "sinc", 0.05);
  const auto linear_odd = Oscillator::errors(1e-5, "linear", 0.05);
  const double bound = std::pow(pi * 440 * 1e-5, 2) / 2;  // linear interpolation of a sinusoid
  std::printf(
      "position errors: exact %.2e, sinc %.2e, linear %.2e; h = 1e-5: sinc %.2e, linear "
      "%.2e (bound %.2e)\n",
      exact[0], sinc[0], linear[0], sinc_odd[0], linear_odd[0], bound);
  for (int q = 0; q < 3; ++q) {
    EXPECT_LT(exact[q], 2e-6);
    // The windowed sinc is a low-pass filter, not an interpolator through the steps: even at
    // step times it weighs the neighbours, and its passband (440 Hz here) deviates by a few 1e-6.
    EXPECT_LT(sinc[q], 2e-5);
    EXPECT_LT(linear[q], 2e-6);  // at step times the line passes through the step's value
    EXPECT_LT(sinc_odd[q], 2e-5);
    EXPECT_LT(linear_odd[q], bound * 1.05);
  }
  EXPECT_GT(linear_odd[0], bound * 0.3);  // the bound is the right size, not vacuous
}

// The friction law: it pulls a along b's relative velocity (b held back by the opposite), is
// viscous below the stick velocity, and falls from N mu_s toward N mu_d as the sliding speed
// grows.
TEST(sound, FrictionLinkOpposesSlidingAndFallsWithSpeed) {
  const Friction::Params p{2.0, 0.8, 0.3, 0.2, 0.05};
  const Vec3 x{}, still{};
  auto f = [&](Vec3 vb) { return Friction::force(x, x, still, vb, p); };
  const Vec3 slow = f({0, 0, 1e-4}), fast = f({0, 0, 100}), mid = f({0, 0, 0.2});
  EXPECT_GT(slow.z, 0);                                        // on a: along w = v_b - v_a
  EXPECT_NEAR(slow.z, 2.0 * 0.8 * 1e-4 / 0.05, 1e-5);          // viscous, slope N mu_s / eps
  EXPECT_NEAR(fast.z, 2.0 * (0.3 + 0.5 * 0.2 / 100.2), 1e-4);  // toward N mu_d
  EXPECT_GT(mid.z, fast.z);                                    // a falling curve
  EXPECT_NEAR(norm(f({3, 0, 4})), norm(f({0, 5, 0})), 1e-12);  // isotropic
  EXPECT_EQ(Friction::damping(p), 2.0 * 0.8 / 0.05);           // the stability estimate's term
}

// The bowed string keeps sounding at the string's fundamental (a little flat, as a bowed
// string under a heavy bow is) with a sawtooth's harmonics at the bridge: Helmholtz motion.
TEST(sound, BowedStringSustainsItsFundamentalWithAllHarmonics) {
  const WavData w = run_example_to_wav("sound_bowed_string");
  ASSERT_EQ(w.channels.size(), 2u);
  const auto& bridge = w.channels[1];
  const double f1 = 219.8855;  // the plucked string's (same string)
  const spectrum::Peak p = spectrum::dominant(from(bridge, 0.5, w.rate), w.rate, 50, 400);
  std::printf("bowed: fundamental %.3f Hz (the string's %.3f Hz)\n", p.frequency, f1);
  EXPECT_LT(std::abs(p.frequency - f1) / f1, 0.02);
  double bin = 0;
  const auto mag = spectrum::magnitude(from(bridge, 0.5, w.rate), w.rate, 8, bin);
  for (int n = 2; n <= 4; ++n) {
    const auto h = spectrum::peaks(mag, bin, n * p.frequency * 0.98, n * p.frequency * 1.02, 0, 0);
    ASSERT_FALSE(h.empty()) << "harmonic " << n;
    const double db = 20 * std::log10(h.front().magnitude / p.magnitude);
    std::printf("bowed: harmonic %d at %.3f Hz, %.1f dB (a sawtooth: %.1f dB)\n", n,
                h.front().frequency, db, -20 * std::log10(n));
    EXPECT_GT(db, -20 * std::log10(n) - 6);
  }
  // Sustained: the last quarter second is as loud as the one after the start.
  auto rms = [&](double t0, double t1) {
    double sum = 0;
    const auto a = std::size_t(t0 * w.rate), b = std::size_t(t1 * w.rate);
    for (std::size_t i = a; i < b; ++i) sum += double(bridge[i]) * bridge[i];
    return std::sqrt(sum / double(b - a));
  };
  EXPECT_GT(rms(1.25, 1.5), 0.7 * rms(0.25, 0.5));
}

}  // namespace
}  // namespace maille
