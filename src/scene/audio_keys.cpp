// [[listen]]'s and [audio]'s keys (audio_keys.hpp), in the order listen_table.cpp reads them.
#include "audio_keys.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <string>

#include "scene_digest.hpp"

namespace maille {

std::span<const StageKey<audio::Listener>> listen_keys() {
  using L = audio::Listener;
  static const std::array<StageKey<L>, 5> keys{
      point_reference<L>("point", {.doc = "`\"name\"`, `\"group:index\"` or a global index",
                                   .default_doc = "required unless `group`",
                                   .range_doc = "an existing point"}),
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
      number_or_auto<&A::gain>("gain", Bound::positive, 0, 1e30,
                               {.doc = "`auto`: 0.99 of full scale at the peak, one gain per "
                                       "quantity; a number: sample = gain × value",
                                .range_doc = "> 0"}),
      choice<&A::resampler>("resampler",
                            {.doc = "when the step does not divide 1 / rate: band-limited "
                                    "windowed sinc, or linear interpolation"}),
      integer<&A::osc_port>("osc_port", 1024, 65535,
                            {.doc = "`maille play`: the UDP port of the OSC server; required by "
                                    "any control with `osc` (docs/sound.md)",
                             .default_doc = "none"}),
      checked(text<&A::osc_host>("osc_host", {.doc = "`maille play`: the address the OSC server "
                                                     "listens on (`\"0.0.0.0\"`: every interface)",
                                              .range_doc = "not empty"}),
              [](SceneTable& t, const A& a) {
                if (a.osc_host.empty())
                  t.fail("osc_host", "must not be empty (an address: \"127.0.0.1\")");
              }),
      checked(text<&A::midi_port>("midi_port", {.doc = "`maille play`: the name of the virtual "
                                                       "MIDI input port it creates (client "
                                                       "`maille-midi`; JACK MIDI when the audio "
                                                       "goes through JACK, else the ALSA "
                                                       "sequencer)",
                                                .range_doc = "not empty"}),
              [](SceneTable& t, const A& a) {
                if (a.midi_port.empty()) t.fail("midi_port", "must not be empty (a port name)");
              }),
  };
  return keys;
}

namespace {

// midi = "cc:N" | "note" | "pitchbend": the source and, for "cc:N", its controller.
void read_midi(SceneTable& t, audio::Control& c, const StageKey<audio::Control>& k) {
  if (!t.has(k.key)) return;
  const std::string s = t.text(k.key, "");
  if (s == "note") {
    c.midi = audio::MidiSource::note;
  } else if (s == "pitchbend") {
    c.midi = audio::MidiSource::pitchbend;
  } else if (s.rfind("cc:", 0) == 0) {
    std::size_t used = 0;
    int n = -1;
    try {
      n = std::stoi(s.substr(3), &used);
    } catch (const std::exception&) {
    }
    if (n < 0 || n > 127 || used != s.size() - 3)
      t.fail(k.key, "'" + s + "': a controller number is 0 to 127 (\"cc:74\")");
    c.midi = audio::MidiSource::cc;
    c.midi_number = n;
  } else {
    t.fail(k.key, "'" + s +
                      "' is not a MIDI source: \"cc:N\" (N 0 to 127), \"note\" or "
                      "\"pitchbend\"");
  }
}

// range = [low, high]: two different finite numbers (required: a control's `key` is given).
void read_range(SceneTable& t, audio::Control& c, const StageKey<audio::Control>& k) {
  const auto r = t.numbers(k.key);
  if (!r || r->size() != 2)
    t.fail(k.key, "is required with 'key': two numbers, range = [low, high]");
  c.low = (*r)[0];
  c.high = (*r)[1];
  if (!std::isfinite(c.low) || !std::isfinite(c.high) || c.low == c.high)
    t.fail(k.key, "must be two different finite numbers");
}

bool has_key(const audio::Control& c) {
  return !c.key.empty();
}

}  // namespace

std::span<const StageKey<audio::Control>> control_keys() {
  using C = audio::Control;
  static const std::array<StageKey<C>, 7> keys{
      parsed<C>("midi", KeyType::text,
                {.doc = "the MIDI source",
                 .default_doc = "none",
                 .range_doc = "`\"cc:N\"` (N 0 to 127), `\"note\"`, `\"pitchbend\"`"},
                read_midi),
      only_if(
          integer<&C::midi_channel>(
              "midi_channel", 1, 16,
              {.doc = "with `midi`: only messages on this channel", .default_doc = "any"}),
          [](const C& c) { return c.midi != audio::MidiSource::none; }, "needs 'midi'"),
      checked(text<&C::osc>("osc", {.doc = "messages to this address, first argument a float (or "
                                           "double, or integer) in [0, 1]",
                                    .default_doc = "none",
                                    .range_doc = "an OSC address: starts with `/`, no space nor "
                                                 "`# * , ? [ ] { }`"}),
              [](SceneTable& t, const C& c) {
                if (c.osc.size() < 2 || c.osc[0] != '/' ||
                    c.osc.find_first_of(" #*,?[]{}") != std::string::npos)
                  t.fail("osc", "'" + c.osc +
                                    "' is not an OSC address: it starts with '/' and has no space "
                                    "or any of # * , ? [ ] { }");
              }),
      checked(text<&C::key>("key", {.doc = "the value to change",
                                    .default_doc = "none",
                                    .range_doc = "a `--set` key of a model parameter"}),
              [](SceneTable& t, const C& c) {
                if (c.key.empty() || c.key.find('=') != std::string::npos ||
                    c.key.find_first_of(" \t") != std::string::npos)
                  t.fail("key",
                         "must be a scene key as --set takes it (\"fields.wind.speed\", "
                         "\"membrane[0].pretension\")");
                // The output tables, and [simulation] (the run, not the model).
                auto output = [&](std::string_view table) { return c.key.rfind(table, 0) == 0; };
                if (output("simulation") ||
                    std::any_of(kOutputTables.begin(), kOutputTables.end(), output))
                  t.fail("key", "'" + c.key +
                                    "' cannot change while a model plays: a control's key is "
                                    "a parameter of the model (links, fields, masses, drives)");
              }),
      only_if(parsed<C>("range", KeyType::custom,
                        {.unit = "the key's",
                         .doc = "where 0 and 127 (MIDI), 0 and 1 (OSC) land",
                         .default_doc = "required with `key`",
                         .range_doc = "two different finite numbers",
                         .type_doc = "[low, high]"},
                        read_range),
              has_key, "maps a value onto 'key': give 'key' too"),
      only_if(
          number<&C::smooth>(
              "smooth", Bound::non_negative, 0, 10,
              {.unit = "s", .doc = "with `key`: the glide from the current value to a new one"}),
          has_key, "glides a 'key': give 'key' too"),
      // A sub-table whose keys are excite_keys(); its `point` names a point of the model, so
      // control_table.cpp reads it.
      custom<C>("excite", KeyType::table,
                {.doc = "a strike or a pluck: `excite` below",
                 .default_doc = "none",
                 .type_doc = "inline table"}),
  };
  return keys;
}

std::span<const StageKey<audio::Excitation>> excite_keys() {
  using X = audio::Excitation;
  static const std::array<StageKey<X>, 4> keys{
      point_reference<X>(
          "point", {.doc = "a point or a whole group (every point of it); only free points",
                    .default_doc = "required",
                    .range_doc = "`\"name\"`, `\"group:index\"`, an index or a group's name"}),
      checked(choice<&X::quantity>("quantity",
                                   {.doc = "`velocity`: amount × s added along `axis` to each "
                                           "point's velocity (a strike: an impulse of m × that); "
                                           "`position`: each point moved by amount × s (a pluck)",
                                    .range_doc = "`velocity`, `position`"}),
              [](SceneTable& t, const X& x) {
                if (x.quantity == audio::Quantity::force)
                  t.fail("quantity",
                         "an excitation changes a velocity (a strike) or a position (a pluck): "
                         "\"velocity\" or \"position\"");
              }),
      checked(
          vector<&X::axis>("axis", {.doc = "the direction (normalised)", .range_doc = "non-zero"}),
          [](SceneTable& t, const X& x) {
            if (!(norm(x.axis) > Real(1e-12))) t.fail("axis", "must not be zero");
          }),
      // A number whose unit in messages follows `quantity` (read before it).
      StageKey<X>{"amount",
                  KeyType::number,
                  {.unit = "m/s or m",
                   .doc = "per unit of the source's strength s: m/s for `velocity`, m for "
                          "`position`; not zero",
                   .default_doc = "required"},
                  Bound::any,
                  -1e3,
                  1e3,
                  [](SceneTable& t, X& x, const StageKey<X>& k) {
                    x.amount = t.real(k.key, Bound::any);
                    if (x.amount == 0) t.fail(k.key, "must not be zero");
                    t.check_range(k.key, Real(x.amount), k.lo, k.hi,
                                  x.quantity == audio::Quantity::velocity ? "m/s" : "m");
                  }},
  };
  return keys;
}

}  // namespace maille
