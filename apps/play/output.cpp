// Choosing a driver (audio_output.hpp): the one named, or JACK, then PulseAudio, then ALSA.
#include "audio_output.hpp"

namespace maille::play {

const std::vector<std::string>& drivers() {
  static const std::vector<std::string> all{"jack", "pulse", "alsa"};
  return all;
}

std::unique_ptr<AudioOutput> open_output(const OutputRequest& r,
                                         const CallbackFactory& make_callback,
                                         std::vector<std::string>& tried) {
  const std::vector<std::string> order =
      r.driver.empty() ? drivers() : std::vector<std::string>{r.driver};
  for (const std::string& d : order) {
    OutputRequest one = r;
    one.driver = d;
    std::string why;
    std::unique_ptr<AudioOutput> out =
        d == "jack" ? open_jack(one, make_callback, why) : open_rtaudio(one, make_callback, why);
    if (out) return out;
    tried.push_back(d + ": " + why);
  }
  return nullptr;
}

}  // namespace maille::play
