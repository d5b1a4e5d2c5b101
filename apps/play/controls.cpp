// The control inputs of `maille play` and the viewer (controls.hpp): a virtual MIDI input port
// (RtMidi: JACK MIDI when the audio goes through JACK, else the ALSA sequencer; RtMidi's own
// default would try ALSA first) and an OSC server (a UDP socket of its own, bound to [audio]
// osc_host : osc_port, messages decoded by liblo). Both push ControlEvents into their rings from
// their own threads.
#include "controls.hpp"

#include "audio_output.hpp"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <iostream>
#include <thread>
#include <vector>

#ifdef MAILLE_WITH_RTMIDI
#include <rtmidi/RtMidi.h>
#endif
#ifdef MAILLE_WITH_OSC
#include <arpa/inet.h>
#include <lo/lo.h>
#include <netinet/in.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>
#endif

namespace maille::play {

#ifdef MAILLE_WITH_RTMIDI
namespace {

class MidiInput final : public ControlInput {
 public:
  MidiInput(const audio::AudioSpec& spec, ControlRings& rings) : spec_(spec), rings_(rings) {}
  bool open(bool jack, std::string& why) {
    try {
      const auto api = jack ? RtMidi::UNIX_JACK : RtMidi::LINUX_ALSA;
      in_ = std::make_unique<RtMidiIn>(api, "maille-midi");
      in_->setCallback(&MidiInput::message, this);
      in_->ignoreTypes(true, true, true);
      in_->openVirtualPort(spec_.settings.midi_port);
      api_ = jack ? "JACK MIDI" : "ALSA sequencer";
      return true;
    } catch (const RtMidiError& e) {
      why = e.getMessage();
      return false;
    }
  }
  std::string describe() const override {
    return "MIDI: virtual input port '" + spec_.settings.midi_port + "' (" + api_ + ")";
  }

 private:
  static void message(double, std::vector<unsigned char>* msg, void* self) {
    auto* me = static_cast<MidiInput*>(self);
    audio::ControlEvent events[16];
    const std::size_t n = audio::midi_events(me->spec_, msg->data(), msg->size(), events, 16);
    for (std::size_t i = 0; i < n; ++i) me->rings_.midi.push(events[i]);
  }

  const audio::AudioSpec spec_;  // a copy: the scene may go while the input runs
  ControlRings& rings_;
  std::unique_ptr<RtMidiIn> in_;
  std::string api_;
};

}  // namespace

std::unique_ptr<ControlInput> open_midi(const audio::AudioSpec& spec, ControlRings& rings,
                                        bool jack, std::string& why) {
  auto in = std::make_unique<MidiInput>(spec, rings);
  if (!in->open(jack, why)) return nullptr;
  return in;
}
#else
std::unique_ptr<ControlInput> open_midi(const audio::AudioSpec&, ControlRings&, bool,
                                        std::string& why) {
  return built_without(why, "RtMidi", "librtmidi-dev");
}
#endif

#ifdef MAILLE_WITH_OSC
namespace {

class OscInput final : public ControlInput {
 public:
  OscInput(const audio::AudioSpec& spec, ControlRings& rings)
      : spec_(spec), rings_(rings), reported_(spec.controls.size(), 0) {}
  ~OscInput() override {
    stop_ = true;
    if (thread_.joinable()) thread_.join();
    if (socket_ >= 0) ::close(socket_);
  }

  bool open(std::string& why) {
    socket_ = ::socket(AF_INET, SOCK_DGRAM, 0);
    sockaddr_in a{};
    a.sin_family = AF_INET;
    a.sin_port = htons(static_cast<std::uint16_t>(spec_.settings.osc_port));
    if (::inet_pton(AF_INET, spec_.settings.osc_host.c_str(), &a.sin_addr) != 1) {
      why = "'" + spec_.settings.osc_host + "' is not an IPv4 address";
      return false;
    }
    if (socket_ < 0 || ::bind(socket_, reinterpret_cast<sockaddr*>(&a), sizeof a) != 0) {
      why = "cannot listen on UDP " + spec_.settings.osc_host + ":" +
            std::to_string(spec_.settings.osc_port) + ": " + std::strerror(errno);
      return false;
    }
    thread_ = std::thread([this] { serve(); });
    return true;
  }
  std::string describe() const override {
    return "OSC: UDP " + spec_.settings.osc_host + ":" + std::to_string(spec_.settings.osc_port);
  }

 private:
  void serve() {
    std::vector<char> data(65536);
    while (!stop_) {
      pollfd p{socket_, POLLIN, 0};
      if (::poll(&p, 1, 50) <= 0) continue;
      const ssize_t n = ::recv(socket_, data.data(), data.size(), 0);
      if (n > 0) handle(data.data(), n);
    }
  }

  // One message: every control on its address gets its first numeric argument.
  void handle(char* data, ssize_t size) {
    int result = 0;
    lo_message m = lo_message_deserialise(data, static_cast<std::size_t>(size), &result);
    if (!m) return;
    const char* path = lo_get_path(data, size);
    const char* types = lo_message_get_types(m);
    lo_arg** argv = lo_message_get_argv(m);
    double v = std::nan("");
    if (types && types[0] == 'f') v = argv[0]->f;
    if (types && types[0] == 'd') v = argv[0]->d;
    if (types && types[0] == 'i') v = argv[0]->i;
    for (std::size_t c = 0; path && c < spec_.controls.size(); ++c) {
      const audio::Control& ctl = spec_.controls[c];
      if (ctl.osc.empty() || ctl.osc != path) continue;
      double x = v;
      if (!(x >= 0 && x <= 1)) {  // clamped, and said once per control
        x = std::isnan(v) ? 0.0 : std::clamp(v, 0.0, 1.0);
        if (!reported_[c]) {
          reported_[c] = 1;
          std::fprintf(stderr,
                       "maille: warning: %s: OSC %s sent %s (a float in [0, 1] is expected): "
                       "clamped to %g (said once)\n",
                       ctl.name.c_str(), path,
                       types && types[0] ? std::to_string(v).c_str() : "no number", x);
        }
      }
      const float f = static_cast<float>(x);
      rings_.osc.push({static_cast<std::uint32_t>(c), f, f});
    }
    lo_message_free(m);
  }

  const audio::AudioSpec spec_;  // a copy: the scene may go while the input runs
  ControlRings& rings_;
  std::vector<char> reported_;
  int socket_ = -1;
  std::atomic<bool> stop_{false};
  std::thread thread_;
};

}  // namespace

std::unique_ptr<ControlInput> open_osc(const audio::AudioSpec& spec, ControlRings& rings,
                                       std::string& why) {
  auto in = std::make_unique<OscInput>(spec, rings);
  if (!in->open(why)) return nullptr;
  return in;
}
#else
std::unique_ptr<ControlInput> open_osc(const audio::AudioSpec&, ControlRings&, std::string& why) {
  return built_without(why, "liblo", "liblo-dev");
}
#endif

}  // namespace maille::play
