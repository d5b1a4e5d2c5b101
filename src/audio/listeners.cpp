// Listeners: the "listen" stage reads the points of the [[listen]] tables at every step's force
// pass, and the Recorder turns those readings into channels at the audio rate.
//
// Why in the force pass: between steps the state holds x(n+1), leapfrog's v(n+1/2) and the
// forces of t_n, three different times. During the force pass of step n everything belongs to
// t_n: x_n, the complete force f_n (this stage runs after every other force stage), and the
// velocity, which a staggered scheme holds at n - 1/2 and which is synchronised here the way the
// simulator does it for energies: v_n = v(n - 1/2) + (h / 2) f_n / m. So the sample of step n is
// the scheme's own state at t_n, exactly.
#include <cmath>
#include <sstream>
#include <stdexcept>

#include "listen_value.hpp"
#include "maille/audio.hpp"
#include "maille/simulator.hpp"

namespace maille::audio {

SamplingPlan plan_sampling(double step, int rate, Resampler resampler) {
  SamplingPlan p;
  p.step = step;
  p.rate = rate;
  p.resampler = resampler;
  const double k = 1.0 / (step * rate);  // steps per sample
  const double whole = std::round(k);
  p.exact = whole >= 1 && std::abs(whole * step * rate - 1) <= 1e-9;
  p.steps_per_sample = p.exact ? static_cast<std::uint64_t>(whole) : 0;
  return p;
}

std::string SamplingPlan::describe() const {
  std::ostringstream s;
  s.precision(6);
  if (exact) {
    s << "exact: every " << steps_per_sample << (steps_per_sample == 1 ? " step" : " steps")
      << " (h = 1/" << steps_per_sample * std::uint64_t(rate) << " s)";
  } else {
    s << "resampled ("
      << (resampler == Resampler::sinc ? "band-limited windowed sinc" : "linear interpolation")
      << "): h = " << step << " s is not 1/(K x " << rate << ") for a whole K ("
      << 1.0 / (step * rate) << " steps per sample)";
  }
  return s.str();
}

struct Recorder::Tap {
  AudioSpec spec;
  SamplingPlan plan;
  std::vector<Vec3> origin;  // initial positions of the listened points (position is measured
                             // from them)
  std::vector<std::vector<float>> exact;     // when plan.exact
  std::vector<StreamResampler> resampled;    // when not
  std::vector<std::vector<float>> channels;  // after finish()
  std::uint64_t next_step = 0;               // the step whose force pass comes next
  std::uint64_t heard = 0;
  bool finished = false;

  void hear(const Model& m, const State& s, const StageContext& ctx) {
    if (finished || ctx.step != next_step) return;  // another pass of a step already heard
    next_step = ctx.step + 1;
    ++heard;
    const bool keep = !plan.exact || ctx.step % plan.steps_per_sample == 0;
    if (!keep) return;
    for (std::size_t c = 0; c < spec.listeners.size(); ++c) {
      const double value = listened_value(spec.listeners[c], origin[c], m, s, ctx);
      if (plan.exact)
        exact[c].push_back(static_cast<float>(value));
      else
        resampled[c].push(value);
    }
  }
};

namespace {

// The last force stage: reads, never writes.
class ListenStage final : public ForceStage {
 public:
  explicit ListenStage(std::shared_ptr<Recorder::Tap> tap) : tap_(std::move(tap)) {}
  std::string name() const override { return std::string(kListenStage); }
  bool reads_only() const override { return true; }
  void apply(const Model& m, State& s, const StageContext& ctx) override { tap_->hear(m, s, ctx); }

 private:
  std::shared_ptr<Recorder::Tap> tap_;
};

}  // namespace

Recorder::Recorder(AudioSpec spec, double step, bool force_resample)
    : tap_(std::make_shared<Tap>()) {
  if (spec.listeners.empty()) throw std::invalid_argument("no listener: add a [[listen]] table");
  if (!(spec.settings.rate >= min_rate && spec.settings.rate <= max_rate))
    throw std::invalid_argument("audio rate out of range");
  tap_->plan = plan_sampling(step, spec.settings.rate, spec.settings.resampler);
  if (force_resample) tap_->plan.exact = false, tap_->plan.steps_per_sample = 0;
  const std::size_t n = spec.listeners.size();
  if (tap_->plan.exact)
    tap_->exact.resize(n);
  else
    for (std::size_t c = 0; c < n; ++c)
      tap_->resampled.emplace_back(step, spec.settings.rate, spec.settings.resampler);
  tap_->spec = std::move(spec);
}

Recorder::~Recorder() = default;

void Recorder::attach(Simulator& sim) {
  const Model& m = sim.model();
  if (sim.backend())
    throw std::invalid_argument(
        "[[listen]] reads its points on the host at every step, and the " + sim.settings().backend +
        " backend keeps the state on the device: record sound with --backend cpu");
  if (sim.steps_taken() != 0 || sim.time() != 0)
    throw std::invalid_argument(
        "listening starts at t = 0 (sample k is the state at k / rate): this simulation is at "
        "step " +
        std::to_string(sim.steps_taken()));
  if (sim.settings().step != tap_->plan.step)
    throw std::invalid_argument("the recorder was planned for another step");
  tap_->origin.clear();
  for (const Listener& l : tap_->spec.listeners) {
    if (l.point >= m.points.size())
      throw std::invalid_argument("listener '" + l.label + "': no point " +
                                  std::to_string(l.point));
    tap_->origin.push_back(m.points.initial_position[l.point]);
  }
  tap_->next_step = sim.steps_taken();
  sim.add_stage(std::make_unique<ListenStage>(tap_));
}

void Recorder::finish() {
  Tap& t = *tap_;
  if (t.finished) return;
  t.finished = true;
  if (t.plan.exact) {
    t.channels = std::move(t.exact);
  } else {
    for (auto& r : t.resampled) {
      r.finish();
      t.channels.push_back(std::move(r.out()));
    }
  }
  // A blow-up leaves non-finite values at the end: every channel stops before the first.
  std::size_t length = t.channels.empty() ? 0 : t.channels[0].size();
  for (const auto& ch : t.channels) {
    length = std::min(length, ch.size());
    for (std::size_t i = 0; i < length; ++i)
      if (!std::isfinite(ch[i])) {
        length = i;
        break;
      }
  }
  for (auto& ch : t.channels) ch.resize(length);
}

const std::vector<std::vector<float>>& Recorder::channels() const {
  return tap_->channels;
}
const AudioSpec& Recorder::spec() const {
  return tap_->spec;
}
const SamplingPlan& Recorder::plan() const {
  return tap_->plan;
}
std::uint64_t Recorder::steps_heard() const {
  return tap_->heard;
}

std::vector<double> output_gains(const std::vector<std::vector<float>>& channels,
                                 const AudioSpec& spec) {
  std::vector<double> gains(channels.size(), spec.settings.gain);
  if (spec.settings.gain > 0) return gains;
  for (std::size_t c = 0; c < channels.size(); ++c) {
    double peak = 0;
    for (std::size_t d = 0; d < channels.size(); ++d)
      if (spec.listeners[d].quantity == spec.listeners[c].quantity)
        for (const float x : channels[d]) peak = std::max(peak, double(std::abs(x)));
    gains[c] = peak > 0 ? 0.99 / peak : 1.0;
  }
  return gains;
}

}  // namespace maille::audio
