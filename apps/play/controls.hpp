// The [[control]] inputs, shared by `maille play` and the viewer (docs/sound.md): a virtual MIDI
// input port (RtMidi) and an OSC server (UDP, liblo's decoder). Each pushes ControlEvents into
// its own lock-free ring from its own thread; whoever renders the model (the audio callback in
// `maille play`, the physics thread in the viewer) drains both before a block.
#pragma once

#include <memory>
#include <string>

#include "maille/live.hpp"

namespace maille::play {

struct ControlRings {
  audio::SpscRing<audio::ControlEvent, 1024> midi, osc;
  // Every waiting event to `source` (LiveSource::control). No allocation, no lock.
  void drain(audio::LiveSource& source) {
    audio::ControlEvent e;
    while (midi.pop(e)) source.control(e);
    while (osc.pop(e)) source.control(e);
  }
};

class ControlInput {
 public:
  virtual ~ControlInput() = default;
  virtual std::string describe() const = 0;
};

// A virtual MIDI input port named spec.settings.midi_port, on JACK MIDI when `jack`, else the
// ALSA sequencer (RtMidi's own default would try ALSA first). The spec is copied.
std::unique_ptr<ControlInput> open_midi(const audio::AudioSpec& spec, ControlRings& rings,
                                        bool jack, std::string& why);
// An OSC server (UDP) on spec.settings.osc_host : osc_port. A value out of [0, 1] is clamped
// and said once per control on stderr.
std::unique_ptr<ControlInput> open_osc(const audio::AudioSpec& spec, ControlRings& rings,
                                       std::string& why);

}  // namespace maille::play
