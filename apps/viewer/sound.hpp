// The viewer's sound (docs/sound.md, "The viewer's Sound panel"), on the UI thread: opens the
// audio device (play::open_output: JACK, PulseAudio, ALSA) and the scene's [[control]] inputs
// (MIDI, OSC), and hands the physics thread a SoundFeed; the physics thread renders into the
// device's ring (play::RingPlayer), the device's callback copies from it.
#pragma once

#include <array>
#include <memory>
#include <string>
#include <vector>

#include "audio_output.hpp"
#include "controls.hpp"
#include "maille/scene.hpp"
#include "physics_thread.hpp"
#include "ring_player.hpp"

namespace maille::viewer {

class Sound {
 public:
  // What the panel edits (kept across scenes).
  struct Choice {
    int driver = 0;                  // 0: the first that opens; else play::drivers()[driver - 1]
    std::array<char, 128> device{};  // empty: the default
    float gain = 1;                  // times [audio] gain, smoothed by the callback
    int buffer = 256;                // frames per period asked of RtAudio (JACK: the server's)
    int rate = 48000;                // asked of RtAudio (JACK: the server's)
  };
  // What the panel shows.
  struct Report {
    bool on = false;
    std::string output;  // "JACK (server 'x', client 'maille', ports out_1..2)"
    int rate = 0;
    std::size_t period = 0, lead = 0;  // frames
    double latency = 0;                // s: the ring's lead plus the device's own
    std::vector<std::string> inputs;   // "MIDI: virtual input port ...", "OSC: UDP ..."
    std::vector<std::string> notes;    // controls that could not open, and why
    std::vector<std::string> tried;    // when no device opened: each driver and why
    std::string error;                 // when sound could not start at all
    play::RingPlayer::Counters counters;
    double cpu = 0;        // CPU time rendering over the audio's duration, recently
    double cpu_worst = 0;  // the largest block's, over the same interval
  };

  Sound() = default;
  Sound(const Sound&) = delete;
  Sound& operator=(const Sound&) = delete;
  ~Sound() { stop(); }

  Choice& choice() { return choice_; }
  // Opens the device for `scene` and starts the physics' sound; false (the report says why)
  // when the scene has nothing to hear, a control's key is refused or no device opens.
  bool start(const Scene& scene, PhysicsThread& physics);
  // Back to silence: the physics' sound first (it paces on the ring), then the device.
  void stop();
  bool on() const { return bool(output_); }
  void set_gain(float gain);
  // The report, its CPU figures refreshed at most every half second (or now: `refresh`).
  const Report& report(bool refresh = false);

 private:
  Choice choice_;
  Report report_;
  PhysicsThread* physics_ = nullptr;  // the physics playing into player_
  std::shared_ptr<play::RingPlayer> player_;
  std::shared_ptr<play::ControlRings> controls_;
  std::vector<std::unique_ptr<play::ControlInput>> inputs_;
  std::unique_ptr<play::AudioOutput> output_;
  double last_wall_ = 0, last_cpu_ = 0;
  std::uint64_t last_rendered_ = 0;
};

}  // namespace maille::viewer
