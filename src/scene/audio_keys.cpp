// [[listen]]'s and [audio]'s keys (audio_keys.hpp), in the order listen_table.cpp reads them.
#include "audio_keys.hpp"

#include <array>

namespace maille {

std::span<const StageKey<audio::Listener>> listen_keys() {
  using L = audio::Listener;
  static const std::array<StageKey<L>, 5> keys{
      custom<L>("point", KeyType::custom,
                {.doc = "`\"name\"`, `\"group:index\"` or a global index",
                 .default_doc = "required unless `group`",
                 .range_doc = "an existing point",
                 .type_doc = "string or integer"}),
      custom<L>("group", KeyType::text,
                {.doc = "instead of `point`: the group whose point `index` is heard",
                 .default_doc = "none",
                 .range_doc = "an existing group"}),
      custom<L>("index", KeyType::integer,
                {.doc = "with `group`: the point's index in it",
                 .default_doc = "required with `group`",
                 .range_doc = "0 to the group's size − 1"}),
      choice<&L::quantity>(
          "quantity", {.doc = "displacement from the initial position (m), velocity synchronised "
                              "to the sample's time (m/s), total force of the force pass (N; on "
                              "a fixed point, the reaction)"}),
      checked(vector<&L::axis>("axis",
                               {.doc = "the component read (normalised)", .range_doc = "non-zero"}),
              [](SceneTable& t, const L& l) {
                if (!(norm(l.axis) > Real(1e-12))) t.fail("axis", "must not be zero");
              }),
  };
  return keys;
}

std::span<const StageKey<audio::AudioSettings>> audio_keys() {
  using A = audio::AudioSettings;
  static const std::array<StageKey<A>, 7> keys{
      integer<&A::rate>("rate", audio::min_rate, audio::max_rate,
                        {.unit = "Hz",
                         .doc = "samples per second; exact sampling when `step` = 1 / (K rate), "
                                "else resampled"}),
      choice<&A::format>("format", {.doc = "16-bit PCM or 32-bit float samples"}),
      custom<A>("gain", KeyType::custom,
                {.doc = "`auto`: 0.99 of full scale at the peak, one gain per quantity; a "
                        "number: sample = gain × value",
                 .default_doc = "`\"auto\"`",
                 .range_doc = "> 0",
                 .type_doc = "`\"auto\"` or number"}),
      choice<&A::resampler>("resampler",
                            {.doc = "when the step does not divide 1 / rate: band-limited "
                                    "windowed sinc, or linear interpolation"}),
      integer<&A::osc_port>("osc_port", 1024, 65535,
                            {.doc = "`maille play`: the UDP port of the OSC server (docs/sound.md)",
                             .default_doc = "none"}),
      checked(text<&A::osc_host>("osc_host", {.doc = "`maille play`: the address the OSC server "
                                                     "listens on",
                                              .range_doc = "not empty"}),
              [](SceneTable& t, const A& a) {
                if (a.osc_host.empty())
                  t.fail("osc_host", "must not be empty (an address: \"127.0.0.1\")");
              }),
      checked(text<&A::midi_port>("midi_port", {.doc = "`maille play`: the name of the virtual "
                                                       "MIDI input port it creates",
                                                .range_doc = "not empty"}),
              [](SceneTable& t, const A& a) {
                if (a.midi_port.empty()) t.fail("midi_port", "must not be empty (a port name)");
              }),
  };
  return keys;
}

}  // namespace maille
