// The page's sound (Playground::listen, take_listened): the listened channels made as
// `maille run --audio` makes them (src/audio/listeners.cpp, the Recorder), from the same pieces:
// the sampling plan (plan_sampling), the value a listener reads during a step's first force pass
// (audio::listened_value) and the streaming resampler (audio::StreamResampler). The Recorder
// itself is not used because it keeps every sample of the run until it finishes and starts only
// at t = 0; the page takes the samples as they come and continues them across `set`. The browser
// test holds the samples to the native Recorder's (web/tests/reference_audio.txt).
#include <stdexcept>

#include "audio/listen_value.hpp"
#include "playground.hpp"

namespace maille::web {

struct Playground::Listening {
  audio::AudioSpec spec;
  audio::SamplingPlan plan;
  std::vector<Vec3> origin;  // position is measured from the initial positions
  std::vector<audio::StreamResampler> resampled;
  std::vector<float> out;       // interleaved, since the last take
  std::uint64_t next_step = 0;  // the step whose first force pass comes next
  const Simulator* installed_in = nullptr;

  void start(const Scene& scene, const Simulator& sim) {
    spec = scene.audio;
    plan = audio::plan_sampling(sim.settings().step, spec.settings.rate, spec.settings.resampler);
    origin.clear();
    for (const audio::Listener& l : spec.listeners)
      origin.push_back(sim.model().points.initial_position[l.point]);
    resampled.clear();
    if (!plan.exact)
      for (std::size_t c = 0; c < spec.listeners.size(); ++c)
        resampled.emplace_back(plan.step, plan.rate, plan.resampler);
    out.clear();
    next_step = sim.steps_taken();
  }

  // Tap::hear of the Recorder, channel-interleaved.
  void hear(const Model& m, const State& s, const StageContext& ctx) {
    if (ctx.step != next_step) return;  // another pass of a step already heard
    next_step = ctx.step + 1;
    if (plan.exact && ctx.step % plan.steps_per_sample != 0) return;
    const std::size_t n = spec.listeners.size();
    if (plan.exact) {
      for (std::size_t c = 0; c < n; ++c)
        out.push_back(float(audio::listened_value(spec.listeners[c], origin[c], m, s, ctx)));
    } else {
      for (std::size_t c = 0; c < n; ++c)
        resampled[c].push(audio::listened_value(spec.listeners[c], origin[c], m, s, ctx));
      // The resamplers emit in step: the same count on every channel.
      const std::size_t ready = resampled[0].out().size();
      for (std::size_t k = 0; k < ready; ++k)
        for (std::size_t c = 0; c < n; ++c) out.push_back(resampled[c].out()[k]);
      for (auto& r : resampled) r.out().clear();
    }
    // At most ten seconds of samples wait for a page that does not take them.
    const std::size_t limit = std::size_t(10 * plan.rate) * n;
    if (out.size() > 2 * limit) out.erase(out.begin(), out.end() - std::ptrdiff_t(limit));
  }
};

namespace {

// The last force stage at the time it is installed, as the Recorder's "listen": reads only.
class PageListenStage final : public ForceStage {
 public:
  explicit PageListenStage(std::shared_ptr<Playground::Listening> l) : l_(std::move(l)) {}
  std::string name() const override { return "listen"; }
  void apply(const Model& m, State& s, const StageContext& ctx) override { l_->hear(m, s, ctx); }

 private:
  std::shared_ptr<Playground::Listening> l_;
};

}  // namespace

void Playground::listen(Simulator& sim, bool continuing) {
  if (scene_->audio.listeners.empty()) {
    listening_.reset();
    return;
  }
  if (!listening_) listening_ = std::make_shared<Listening>();
  if (!continuing) listening_->start(*scene_, sim);
  listening_->next_step = sim.steps_taken();
  if (listening_->installed_in != &sim) {
    sim.add_stage(std::make_unique<PageListenStage>(listening_));
    listening_->installed_in = &sim;
  }
}

std::vector<float> Playground::take_listened() {
  std::vector<float> out;
  if (listening_) out.swap(listening_->out);
  return out;
}

int Playground::audio_rate() const {
  return listening_ ? listening_->plan.rate : 0;
}

std::string Playground::sampling() const {
  return listening_ ? listening_->plan.describe() : std::string();
}

}  // namespace maille::web
