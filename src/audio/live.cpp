// LiveSource (live.hpp): the model stepped sample by sample for an audio callback. The same
// listen reading as `maille run --audio` (listen_value.hpp), the same sampling plan, so that a
// block rendered here equals the WAV's samples when no control moves.
#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "listen_value.hpp"
#include "maille/live.hpp"
#include "maille/simulator.hpp"

namespace maille::audio {

namespace {

// Parameters are rewritten at most every this many samples while a control glides (0.67 ms at
// 48 kHz): a 20 ms glide is then 30 small steps, and a drum's 1,500 links are not rewritten at
// every sample.
constexpr std::uint32_t kTuneEvery = 32;

// A parameter control's glide: from `current` towards `target`, both in [0, 1].
struct Glide {
  double current = 0, target = 0;
  double per_sample = 1;  // the largest change per sample (1 / (smooth x rate))
  bool moving = false;
};

}  // namespace

struct LiveSource::Impl {
  Simulator& sim;
  AudioSpec spec;
  SamplingPlan plan;
  std::vector<ParameterTable> tables;
  std::vector<Glide> glides;
  std::vector<Vec3> origin;                // initial positions of the listened points
  std::vector<double> value;               // exact plan: the channels at the last sample's step
  std::vector<StreamResampler> resampled;  // otherwise, one per channel
  std::vector<double> peak;                // per channel: the largest |value| heard (auto gain)
  std::vector<double> gain;                // per channel
  std::uint64_t frames = 0, clipped = 0;
  std::uint64_t start_step = 0, next_step = 0;  // sample 0 is heard during step start_step
  std::uint32_t since_tune = 0;
  bool blown = false;
  double blow_time = 0;

  Impl(Simulator& s, const AudioSpec& sp, int rate, std::vector<ParameterTable> t,
       std::size_t max_frames)
      : sim(s), spec(sp), tables(std::move(t)) {
    start_step = next_step = sim.steps_taken();
    plan = plan_sampling(sim.settings().step, rate, spec.settings.resampler);
    const std::size_t n = spec.listeners.size();
    value.assign(n, 0);
    peak.assign(n, 0);
    gain.assign(n, spec.settings.gain > 0 ? spec.settings.gain : 1.0);
    if (!plan.exact)
      for (std::size_t c = 0; c < n; ++c) {
        resampled.emplace_back(sim.settings().step, rate, spec.settings.resampler);
        // Capacity for a block and the kernel's span: no allocation while playing.
        resampled.back().out().reserve(max_frames * 2 + 1024);
        resampled.back().reserve_input(1 << 15);
      }
    tables.resize(spec.controls.size());
    glides.resize(spec.controls.size());
    for (std::size_t c = 0; c < spec.controls.size(); ++c) {
      const double smooth = std::max(spec.controls[c].smooth, 1.0 / rate);
      glides[c].per_sample = 1.0 / (smooth * rate);
      glides[c].current = glides[c].target = tables[c].initial;
    }
  }

  void hear(const Model& m, const State& s, const StageContext& ctx) {
    if (ctx.step != next_step) return;  // another pass of a step already heard
    next_step = ctx.step + 1;
    if (plan.exact && (ctx.step - start_step) % plan.steps_per_sample != 0) return;
    for (std::size_t c = 0; c < spec.listeners.size(); ++c) {
      const double v = listened_value(spec.listeners[c], origin[c], m, s, ctx);
      if (plan.exact)
        value[c] = v;
      else
        resampled[c].push(v);
    }
  }

  // Writes the blend of control c's rows at its glide's current position.
  void tune(std::size_t c) {
    const ParameterTable& t = tables[c];
    const double pos = std::clamp(glides[c].current, 0.0, 1.0) * double(t.rows - 1);
    const std::size_t j = std::min(static_cast<std::size_t>(pos), t.rows - 2);
    const double frac = pos - double(j);
    const std::size_t n = t.slots.size();
    const double* a = &t.values[j * n];
    const double* b = a + n;
    sim.tune_parameters([&](Model& m) {
      for (std::size_t k = 0; k < n; ++k) set_parameter(m, t.slots[k], a[k] + frac * (b[k] - a[k]));
    });
  }

  // One sample's worth of control glides; parameters rewritten every kTuneEvery samples and
  // when a glide arrives.
  void glide() {
    ++since_tune;
    for (std::size_t c = 0; c < glides.size(); ++c) {
      Glide& g = glides[c];
      if (!g.moving) continue;
      const double d = g.target - g.current;
      const bool arrives = std::abs(d) <= g.per_sample;
      g.current = arrives ? g.target : g.current + std::copysign(g.per_sample, d);
      g.moving = !arrives;
      if (arrives || since_tune >= kTuneEvery) tune(c);
    }
    if (since_tune >= kTuneEvery) since_tune = 0;
  }

  void excite(const Excitation& e, double strength) {
    State& s = sim.state_for_editing();
    const Vec3 d = e.axis * static_cast<Real>(e.amount * strength);
    for (const std::uint32_t p : e.points) {
      if (e.quantity == Quantity::position)
        s.x()[p] += d;
      else
        s.v()[p] += d;
    }
  }

  double gain_of(std::size_t c) {
    if (spec.settings.gain > 0) return spec.settings.gain;
    double p = 0;  // the largest |value| of the channels of this quantity
    for (std::size_t d = 0; d < peak.size(); ++d)
      if (spec.listeners[d].quantity == spec.listeners[c].quantity) p = std::max(p, peak[d]);
    return p > 0 ? 0.99 / p : 1.0;
  }

  // The next sample of every channel into `out`; false after a blow-up.
  bool next_sample(float* out) {
    const std::size_t n = value.size();
    if (plan.exact) {
      for (std::uint64_t k = 0; k < plan.steps_per_sample; ++k)
        if (!sim.step()) return false;
    } else {
      while (resampled[0].out().empty())
        if (!sim.step()) return false;
      for (std::size_t c = 0; c < n; ++c) {
        auto& o = resampled[c].out();
        value[c] = o.front();
        o.erase(o.begin());
      }
    }
    for (std::size_t c = 0; c < n; ++c)
      if (!std::isfinite(value[c])) return false;
    for (std::size_t c = 0; c < n; ++c) peak[c] = std::max(peak[c], std::abs(value[c]));
    for (std::size_t c = 0; c < n; ++c) {
      gain[c] = gain_of(c);
      // As `run --audio` writes a float32 WAV: the float sample, then the gain.
      const float y = static_cast<float>(gain[c] * double(static_cast<float>(value[c])));
      clipped += std::abs(y) > 1.0f;
      out[c] = y;
    }
    return true;
  }
};

namespace {

// The last force stage, like the Recorder's "listen": reads, never writes.
class LiveListenStage final : public ForceStage {
 public:
  explicit LiveListenStage(LiveSource::Impl* impl) : impl_(impl) {}
  std::string name() const override { return std::string(kListenStage); }
  bool reads_only() const override { return true; }
  void apply(const Model& m, State& s, const StageContext& ctx) override { impl_->hear(m, s, ctx); }

 private:
  LiveSource::Impl* impl_;
};

}  // namespace

LiveSource::LiveSource(Simulator& sim, const AudioSpec& spec, int rate,
                       std::vector<ParameterTable> tables, std::size_t max_frames)
    : impl_(std::make_unique<Impl>(sim, spec, rate, std::move(tables), max_frames)) {
  if (spec.listeners.empty()) throw std::invalid_argument("no listener: add a [[listen]] table");
  if (sim.backend())
    throw std::invalid_argument(
        "playing reads the state on the host at every step: use the cpu "
        "backend");
  for (const Listener& l : spec.listeners) {
    if (l.point >= sim.model().points.size())
      throw std::invalid_argument("listener '" + l.label + "': no point " +
                                  std::to_string(l.point));
    impl_->origin.push_back(sim.model().points.initial_position[l.point]);
  }
  for (std::size_t c = 0; c < spec.controls.size(); ++c)
    if (!spec.controls[c].key.empty() && impl_->tables[c].rows < 2)
      throw std::invalid_argument(spec.controls[c].name + ": no parameter table");
  auto stage = std::make_unique<LiveListenStage>(impl_.get());
  stage_ = stage.get();
  sim.add_stage(std::move(stage));
}

LiveSource::~LiveSource() {
  impl_->sim.remove_stage(stage_);
}

void LiveSource::control(const ControlEvent& e) {
  Impl& im = *impl_;
  if (e.control >= im.spec.controls.size() || im.blown) return;
  const Control& c = im.spec.controls[e.control];
  const double v = std::clamp(static_cast<double>(e.value), 0.0, 1.0);
  if (c.excite) im.excite(*c.excite, std::clamp(static_cast<double>(e.strength), 0.0, 1.0));
  if (!c.key.empty()) {
    Glide& g = im.glides[e.control];
    g.target = v;
    g.moving = g.target != g.current;
  }
}

void LiveSource::render(float* out, std::size_t frames) {
  Impl& im = *impl_;
  const std::size_t n = im.value.size();
  for (std::size_t i = 0; i < frames; ++i) {
    float* frame = out + i * n;
    if (!im.blown) {
      im.glide();
      if (!im.next_sample(frame)) {
        im.blown = true;
        im.blow_time = double(im.frames) / im.plan.rate;
      }
    }
    if (im.blown) std::fill(frame, frame + n, 0.0f);
    ++im.frames;
  }
}

std::size_t LiveSource::channels() const {
  return impl_->value.size();
}
const SamplingPlan& LiveSource::plan() const {
  return impl_->plan;
}
std::uint64_t LiveSource::frames() const {
  return impl_->frames;
}
bool LiveSource::blown_up() const {
  return impl_->blown;
}
double LiveSource::blow_up_time() const {
  return impl_->blow_time;
}
std::uint64_t LiveSource::clipped() const {
  return impl_->clipped;
}
std::vector<double> LiveSource::gains() const {
  return impl_->gain;
}
double LiveSource::control_value(std::size_t c) const {
  const Control& ctl = impl_->spec.controls.at(c);
  return ctl.low + (ctl.high - ctl.low) * impl_->glides.at(c).current;
}

std::vector<double> LiveSource::control_positions() const {
  std::vector<double> out;
  for (const Glide& g : impl_->glides) out.push_back(g.current);
  return out;
}
void LiveSource::set_control_positions(const std::vector<double>& positions) {
  for (std::size_t c = 0; c < positions.size() && c < impl_->glides.size(); ++c) {
    Glide& g = impl_->glides[c];
    g.current = g.target = std::clamp(positions[c], 0.0, 1.0);
    g.moving = false;
  }
}

std::size_t midi_events(const AudioSpec& spec, const unsigned char* msg, std::size_t size,
                        ControlEvent* out, std::size_t out_size) {
  if (size < 2) return 0;
  const int status = msg[0] & 0xF0, channel = (msg[0] & 0x0F) + 1;
  std::size_t count = 0;
  for (std::size_t c = 0; c < spec.controls.size() && count < out_size; ++c) {
    const Control& ctl = spec.controls[c];
    if (ctl.midi_channel && ctl.midi_channel != channel) continue;
    ControlEvent e{static_cast<std::uint32_t>(c), 0, 0};
    if (ctl.midi == MidiSource::cc && status == 0xB0 && size >= 3 && msg[1] == ctl.midi_number) {
      e.value = e.strength = float(msg[2]) / 127.0f;
    } else if (ctl.midi == MidiSource::note && status == 0x90 && size >= 3 && msg[2] > 0) {
      e.value = float(msg[1]) / 127.0f;     // the note's number places the key
      e.strength = float(msg[2]) / 127.0f;  // its velocity scales the excitation
    } else if (ctl.midi == MidiSource::pitchbend && status == 0xE0 && size >= 3) {
      e.value = e.strength = float(msg[1] | (msg[2] << 7)) / 16383.0f;
    } else {
      continue;
    }
    out[count++] = e;
  }
  return count;
}

}  // namespace maille::audio
