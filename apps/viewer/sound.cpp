#include "sound.hpp"

#include <algorithm>
#include <chrono>
#include <thread>

#include "play_engine.hpp"

namespace maille::viewer {

namespace {

// The ring's lead: two periods (the callback takes one while the physics renders the next) and
// 10 ms for the physics thread's other work between two fills (a snapshot, commands).
std::size_t lead_for(int rate, std::size_t period) {
  return 2 * period + static_cast<std::size_t>(rate / 100);
}

// The CPU figures are averaged over this much wall time (the panel's numbers stay readable).
constexpr double kReportInterval = 0.5;

}  // namespace

bool Sound::start(const Scene& scene, PhysicsThread& physics) {
  stop();
  report_ = Report{};
  const audio::AudioSpec& spec = scene.audio;
  if (spec.listeners.empty()) {
    report_.error = "the scene has no [[listen]] table: nothing to hear (docs/sound.md)";
    return false;
  }
  // Every parameter control's key, read at values across its range and validated, as `maille
  // play` does (the scene's own file, without the viewer's live edits).
  std::vector<audio::ParameterTable> tables(spec.controls.size());
  for (std::size_t c = 0; c < tables.size(); ++c) {
    if (spec.controls[c].key.empty()) continue;
    Result<audio::ParameterTable> t =
        build_parameter_table(scene.source, {}, scene.model, scene.settings, spec.controls[c]);
    if (!t) {
      report_.error = t.error().to_string();
      return false;
    }
    tables[c] = std::move(t.value());
  }

  play::OutputRequest request;
  request.driver = choice_.driver > 0 ? play::drivers()[std::size_t(choice_.driver - 1)] : "";
  request.device = choice_.device.data();
  request.rate = choice_.rate;
  request.buffer = std::size_t(choice_.buffer);
  request.channels = spec.listeners.size();
  request.client = "maille-viewer";
  // The gain starts at 0 and ramps to the chosen one: the model is mid-motion when sound starts.
  auto make = [&](int rate, std::size_t buffer) -> play::AudioCallback* {
    player_ = std::make_shared<play::RingPlayer>(request.channels, rate, lead_for(rate, buffer), 64,
                                                 0.0f);
    player_->set_gain(choice_.gain);
    return player_.get();
  };
  output_ = play::open_output(request, make, report_.tried);
  if (!output_) {
    player_.reset();
    report_.error = "no audio output could be opened; tried:";
    return false;
  }

  controls_ = std::make_shared<play::ControlRings>();
  bool midi = false, osc = false;
  for (const audio::Control& c : spec.controls) {
    midi = midi || c.midi != audio::MidiSource::none;
    osc = osc || !c.osc.empty();
  }
  std::string why;
  if (midi) {
    if (auto in = play::open_midi(spec, *controls_, output_->is_jack(), why))
      inputs_.push_back(std::move(in));
    else
      report_.notes.push_back("the MIDI controls are off: " + why);
  }
  if (osc && spec.settings.osc_port == 0) {
    report_.notes.push_back("the OSC controls are off: [audio] osc_port is not given");
  } else if (osc) {
    if (auto in = play::open_osc(spec, *controls_, why))
      inputs_.push_back(std::move(in));
    else
      report_.notes.push_back("the OSC controls are off: " + why);
  }
  for (const auto& in : inputs_) report_.inputs.push_back(in->describe());

  physics.start_sound({player_, controls_, spec, std::move(tables)});
  physics_ = &physics;
  report_.on = true;
  report_.output = output_->describe();
  report_.rate = output_->rate();
  report_.period = output_->buffer();
  report_.lead = player_->lead();
  report_.latency = double(player_->lead()) / output_->rate() + output_->latency_seconds();
  last_wall_ = play::wall_seconds();
  return true;
}

void Sound::stop() {
  if (physics_) physics_->stop_sound();
  physics_ = nullptr;
  if (!output_) return;
  // A fade to silence before the device closes (the callback's gain ramp), then the device,
  // then the inputs (their rings are shared with the physics, which lets them go).
  player_->set_gain(0.0f);
  std::this_thread::sleep_for(std::chrono::duration<double>(
      play::RingPlayer::kGainRamp + double(output_->buffer()) / output_->rate()));
  output_->stop();
  output_.reset();
  inputs_.clear();
  player_.reset();
  controls_.reset();
  report_.on = false;
}

void Sound::set_gain(float gain) {
  choice_.gain = gain;
  if (player_) player_->set_gain(gain);
}

const Sound::Report& Sound::report(bool refresh_now) {
  if (!player_) return report_;
  const double now = play::wall_seconds();
  const bool refresh = refresh_now || now - last_wall_ >= kReportInterval;
  report_.counters = player_->counters(refresh);
  if (refresh) {
    const std::uint64_t frames = report_.counters.rendered - last_rendered_;
    const double cpu = report_.counters.cpu_seconds - last_cpu_;
    report_.cpu = frames ? cpu * report_.rate / double(frames) : 0.0;
    report_.cpu_worst = report_.counters.worst_block;
    last_wall_ = now;
    last_cpu_ = report_.counters.cpu_seconds;
    last_rendered_ = report_.counters.rendered;
  }
  return report_;
}

}  // namespace maille::viewer
