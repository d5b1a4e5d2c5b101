// Choosing a driver (audio_output.hpp): the one named, or JACK, then PulseAudio, then ALSA.
#include "audio_output.hpp"

namespace maille::play {

const std::vector<std::string>& drivers() {
  static const std::vector<std::string> all{"jack", "pulse", "alsa"};
  return all;
}

namespace {

// The driver r names ("jack", else one of RtAudio's), or nullptr and why not: a driver built
// without its library says so.
std::unique_ptr<AudioOutput> open_driver(const OutputRequest& r,
                                         [[maybe_unused]] const CallbackFactory& make_callback,
                                         std::string& why) {
  if (r.driver == "jack") {
#ifdef MAILLE_WITH_JACK
    return open_jack(r, make_callback, why);
#else
    return built_without(why, "JACK", "libjack-jackd2-dev");
#endif
  }
#ifdef MAILLE_WITH_RTAUDIO
  return open_rtaudio(r, make_callback, why);
#else
  return built_without(why, "RtAudio", "librtaudio-dev");
#endif
}

}  // namespace

std::unique_ptr<AudioOutput> open_output(const OutputRequest& r,
                                         const CallbackFactory& make_callback,
                                         std::vector<std::string>& tried) {
  const std::vector<std::string> order =
      r.driver.empty() ? drivers() : std::vector<std::string>{r.driver};
  for (const std::string& d : order) {
    OutputRequest one = r;
    one.driver = d;
    std::string why;
    std::unique_ptr<AudioOutput> out = open_driver(one, make_callback, why);
    if (out) return out;
    tried.push_back(d + ": " + why);
  }
  return nullptr;
}

}  // namespace maille::play
