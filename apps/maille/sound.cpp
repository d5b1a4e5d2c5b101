#include "sound.hpp"

#include <cmath>
#include <cstdio>
#include <iostream>
#include <ostream>
#include <sstream>
#include <string>

#include "maille/exit_codes.hpp"
#include "maille/io.hpp"
#include "maille/limits.hpp"

namespace maille::app {

namespace {

std::string format_name(audio::SampleFormat f) {
  return std::string(doc_of(f));
}

}  // namespace

void describe_audio(std::ostream& out, const audio::AudioSpec& spec, double step) {
  for (std::size_t c = 0; c < spec.listeners.size(); ++c) {
    const audio::Listener& l = spec.listeners[c];
    out << "listen       channel " << c << ": " << audio::name(l.quantity) << " of " << l.label
        << " (point " << l.point << ") along [" << l.axis.x << ", " << l.axis.y << ", " << l.axis.z
        << "]\n";
  }
  if (spec.listeners.empty()) return;
  const audio::AudioSettings& s = spec.settings;
  out << "audio        " << s.rate << " Hz, " << format_name(s.format) << ", gain ";
  if (s.gain > 0)
    out << s.gain;
  else
    out << "auto (peak at 0.99 of full scale)";
  out << "; " << audio::plan_sampling(step, s.rate, s.resampler).describe() << '\n';
  for (std::size_t c = 0; c < spec.controls.size(); ++c) {  // `maille play`'s controls
    const audio::Control& k = spec.controls[c];
    out << "control      " << c << ":";
    if (k.midi == audio::MidiSource::cc) out << " MIDI cc:" << k.midi_number;
    if (k.midi == audio::MidiSource::note) out << " MIDI note";
    if (k.midi == audio::MidiSource::pitchbend) out << " MIDI pitchbend";
    if (k.midi_channel) out << " (channel " << k.midi_channel << ")";
    if (!k.osc.empty()) out << " OSC " << k.osc;
    if (!k.key.empty()) out << " -> " << k.key << " in [" << k.low << ", " << k.high << "]";
    if (k.excite)
      out << " -> " << (k.excite->quantity == audio::Quantity::position ? "pluck " : "strike ")
          << k.excite->label << " by " << k.excite->amount
          << (k.excite->quantity == audio::Quantity::position ? " m" : " m/s");
    out << '\n';
  }
  if (!spec.controls.empty())
    out << "audio        play: MIDI port '" << s.midi_port << "'"
        << (s.osc_port ? ", OSC on " + s.osc_host + ":" + std::to_string(s.osc_port) : "") << '\n';
}

std::uint64_t planned_wav_bytes(const audio::AudioSpec& spec, double seconds) {
  const double frames = std::floor(seconds * spec.settings.rate) + 1;
  const double bytes = frames * double(spec.listeners.size()) *
                       (spec.settings.format == audio::SampleFormat::pcm16 ? 2 : 4);
  return bytes > 1.8e19 ? ~std::uint64_t{0} : static_cast<std::uint64_t>(bytes);
}

std::uint64_t planned_audio_memory_bytes(const audio::AudioSpec& spec, double seconds) {
  const double frames = std::floor(seconds * spec.settings.rate) + 1;
  const double bytes = frames * double(spec.listeners.size()) * sizeof(float);
  return bytes > 1.8e19 ? ~std::uint64_t{0} : static_cast<std::uint64_t>(bytes);
}

namespace {

const char* unit_of(audio::Quantity q) {
  return q == audio::Quantity::position ? "m" : q == audio::Quantity::force ? "N" : "m/s";
}

}  // namespace

WavReport write_sound(audio::Recorder& recorder, const std::filesystem::path& path) {
  recorder.finish();
  const audio::AudioSpec& spec = recorder.spec();
  const auto& channels = recorder.channels();
  const std::vector<double> gains = audio::output_gains(channels, spec);
  if (path.has_parent_path()) std::filesystem::create_directories(path.parent_path());
  const WavReport r = write_wav(path, channels, spec.settings.rate, spec.settings.format, gains);
  // Per channel: what it is, its gain and where its peak lands.
  std::ostringstream each;
  each.precision(4);
  for (std::size_t c = 0; c < channels.size(); ++c) {
    const audio::Listener& l = spec.listeners[c];
    each << (c ? "; " : "") << c << ": " << audio::name(l.quantity) << " of " << l.label
         << ", gain " << gains[c] << " per " << unit_of(l.quantity) << " (peak " << r.peak[c] << " "
         << unit_of(l.quantity) << " -> " << r.peak[c] * gains[c] << " of full scale)";
  }
  std::printf(
      "maille: audio %s: %d Hz %s, %llu samples (%.4g s), gain %s%s, %s; channels %s\n",
      path.string().c_str(), spec.settings.rate, format_name(spec.settings.format).c_str(),
      static_cast<unsigned long long>(r.frames), double(r.frames) / spec.settings.rate,
      spec.settings.gain > 0 ? "fixed" : "auto (0.99 of full scale at each quantity's peak)",
      r.clipped ? (", " + std::to_string(r.clipped) + " samples clipped").c_str() : "",
      recorder.plan().describe().c_str(), each.str().c_str());
  return r;
}

std::string audio_clash(const std::filesystem::path& audio, const std::filesystem::path& scene,
                        const std::filesystem::path& out) {
  namespace fs = std::filesystem;
  std::error_code ec;
  const fs::path a = fs::weakly_canonical(audio, ec);
  if (ec) return {};
  if (a == fs::weakly_canonical(scene, ec) || fs::equivalent(audio, scene, ec))
    return "it is the scene file";
  const fs::path dir = fs::weakly_canonical(out, ec);
  if (a == dir) return "it is the output directory";
  if (a.parent_path() != dir) return {};
  const std::string name = a.filename().string();
  if (name == "stats.csv" || name == "checkpoint.bin" || name == "stats.csv.tmp" ||
      name == "checkpoint.bin.tmp")
    return "the run writes its " + name + " there";
  if (name.rfind("frame_", 0) == 0)
    for (const auto& f : name_strings<FrameFormat>())
      if (a.extension() == "." + f) return "the run writes its frames under that name";
  return {};
}

int check_audio(const std::string& scene, const audio::AudioSpec& spec, double seconds,
                bool resuming) {
  if (spec.listeners.empty()) {
    std::cerr << scene << ": error: --audio: the scene has no [[listen]] table (docs/sound.md)\n";
    return exit_code::bad_input;
  }
  if (resuming) {
    std::cerr << "error: --audio records from t = 0: it cannot be combined with --resume\n";
    return exit_code::usage;
  }
  if (planned_wav_bytes(spec, seconds) > max_wav_data_bytes) {
    std::cerr << "error: --audio: " << seconds << " s of " << spec.listeners.size()
              << " channels is beyond the 4 GiB a WAV file can hold\n";
    return exit_code::usage;
  }
  // A recording beyond the memory budget would die of it after minutes, losing everything.
  const double held = double(planned_audio_memory_bytes(spec, seconds));
  if (held > double(limits::memory_budget_bytes())) {
    std::cerr << "error: --audio: " << seconds << " s of " << spec.listeners.size()
              << " channels at " << spec.settings.rate
              << " Hz are held in memory until the end, about " << held / double(1 << 30)
              << " GiB, beyond the memory budget of "
              << double(limits::memory_budget_bytes()) / double(1 << 30)
              << " GiB (half the physical memory): shorten the run (--duration) or listen to "
                 "fewer points\n";
    return exit_code::usage;
  }
  return exit_code::ok;
}

}  // namespace maille::app
