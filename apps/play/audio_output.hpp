// The audio device, shared by `maille play` and the viewer's Sound panel (docs/sound.md,
// "Playing live" and "The viewer's Sound panel"): JACK directly, or RtAudio (ALSA, PulseAudio),
// calling an AudioCallback once per period from the device's real-time thread.
//
//   maille play:  the callback is a PlayEngine (play_engine.hpp): it computes the model itself.
//   the viewer:   the callback is a RingPlayer (ring_player.hpp): it copies what the physics
//                 thread rendered into a lock-free ring.
#pragma once

#include <cstddef>
#include <functional>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

namespace maille::play {

// What a driver calls from its real-time thread: nothing in process() or process_interleaved()
// may allocate, lock or do I/O. One virtual call per period.
class AudioCallback {
 public:
  virtual ~AudioCallback() = default;
  // One period: `frames` samples of every channel into out[c] (one buffer per channel: JACK).
  virtual void process(float* const* out, std::size_t frames) = 0;
  // The same, interleaved (RtAudio).
  virtual void process_interleaved(float* out, std::size_t frames) = 0;
  // The driver missed a deadline (JACK's xrun callback, RtAudio's underflow flag).
  virtual void xrun() = 0;
};

// The device side. open_*() return nullptr and say why in `why` when they cannot start.
class AudioOutput {
 public:
  virtual ~AudioOutput() = default;
  virtual std::string describe() const = 0;  // "JACK (server default, client maille)"
  virtual double latency_seconds() const = 0;
  virtual int rate() const = 0;
  virtual std::size_t buffer() const = 0;  // frames per period
  virtual bool is_jack() const = 0;        // MIDI then goes through the same server
  virtual void stop() = 0;
};

struct OutputRequest {
  std::string driver;  // "jack", "alsa", "pulse"; empty: JACK, then PulseAudio, then ALSA
  std::string device;  // empty: the default
  int rate = 48000;
  std::size_t buffer = 64;
  std::size_t channels = 1;
  std::string client = "maille";  // JACK client name (RtAudio's stream name)
};

// The drivers a request may name, in the order an empty one tries them.
const std::vector<std::string>& drivers();

// Opens the device; `make_callback(rate, buffer)` is called once the stream's rate and period
// are known and before it starts (nullptr: the model cannot play so; the attempt fails). The
// callback must outlive the output (or its stop()). Returns nullptr with every attempt's reason
// in `tried` ("jack: no JACK server running ...").
using CallbackFactory = std::function<AudioCallback*(int rate, std::size_t buffer)>;
std::unique_ptr<AudioOutput> open_output(const OutputRequest& r,
                                         const CallbackFactory& make_callback,
                                         std::vector<std::string>& tried);
// The drivers, in builds with their library (open_output answers for the others).
std::unique_ptr<AudioOutput> open_jack(const OutputRequest& r, const CallbackFactory& make_callback,
                                       std::string& why);
std::unique_ptr<AudioOutput> open_rtaudio(const OutputRequest& r,
                                          const CallbackFactory& make_callback, std::string& why);

// The drivers' and control inputs' shared steps. An output once started (its start() said yes),
// else nullptr with start()'s reason in `why`.
template <class Output>
std::unique_ptr<AudioOutput> started(std::unique_ptr<Output> out, const OutputRequest& r,
                                     const CallbackFactory& make_callback, std::string& why) {
  if (!out->start(r, make_callback, why)) return nullptr;
  return out;
}
// What a driver or input built without its library answers: nullptr, and in `why` the library
// and the package that brings it ("this maille was built without JACK (libjack-jackd2-dev; ...").
inline std::nullptr_t built_without(std::string& why, std::string_view library,
                                    std::string_view package) {
  why = std::string("this maille was built without ")
            .append(library)
            .append(" (")
            .append(package)
            .append("; scripts/setup.sh installs it)");
  return nullptr;
}

}  // namespace maille::play
