// [[control]]: a MIDI and/or OSC source mapped onto a scene key or an excitation (`maille play`,
// docs/sound.md "Controls"). What can be checked from the file is checked here; whether the key
// may change while the model plays is checked when playing starts (control_keys.cpp), since it
// needs the scene read again.
#include <algorithm>
#include <cmath>
#include <string>

#include "audio_keys.hpp"
#include "listen_table.hpp"

namespace maille {

namespace {

void read_midi(TomlCursor& t, audio::Control& c) {
  if (!t.has("midi")) {
    if (t.has("midi_channel")) t.fail("midi_channel", "needs 'midi'");
    return;
  }
  const std::string s = t.text("midi");
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
      t.fail("midi", "'" + s + "': a controller number is 0 to 127 (\"cc:74\")");
    c.midi = audio::MidiSource::cc;
    c.midi_number = n;
  } else {
    t.fail("midi", "'" + s +
                       "' is not a MIDI source: \"cc:N\" (N 0 to 127), \"note\" or "
                       "\"pitchbend\"");
  }
  read_key(t, c, control_keys(), "midi_channel");
}

// The points an excitation acts on: a point (name, "group:index", index) or a whole group.
std::vector<std::uint32_t> excited_points(TomlCursor& e, const Model& m, std::string& label) {
  std::vector<std::uint32_t> points;
  const toml::node* n = e.node("point");
  if (!n) e.fail("point", "is required: a point name, \"group:index\", an index or a group");
  if (n->is_string() && n->value<std::string>()->find(':') == std::string::npos) {
    label = *n->value<std::string>();
    const Group* g = m.group(label);
    if (!g) e.fail("point", "no point or group named '" + label + "'");
    for (std::uint32_t i = 0; i < g->count; ++i) points.push_back(g->first + i);
  } else {
    points.push_back(listened_point(e, m, label));
  }
  for (const std::uint32_t p : points)
    if (m.points.kind[p] != PointKind::free)
      e.fail("point", "'" + label + "' has a " + std::string(to_string(m.points.kind[p])) +
                          " point (" + std::to_string(p) + "): only free points can be excited");
  return points;
}

audio::Excitation excitation(TomlCursor& e, const Model& m) {
  audio::Excitation x;
  x.points = excited_points(e, m, x.label);
  read_key(e, x, excite_keys(), "quantity");
  read_key(e, x, excite_keys(), "axis");
  x.axis = x.axis / norm(x.axis);
  x.amount = e.real("amount", Bound::any);
  if (x.amount == 0) e.fail("amount", "must not be zero");
  const auto& amount = *std::find_if(excite_keys().begin(), excite_keys().end(),
                                     [](const auto& k) { return k.key == "amount"; });
  e.check_range("amount", Real(x.amount), amount.lo, amount.hi,
                x.quantity == audio::Quantity::velocity ? "m/s" : "m");
  e.finish();
  return x;
}

audio::Control control(TomlCursor& t, const Model& m, std::size_t index) {
  audio::Control c;
  c.name = "control[" + std::to_string(index) + "]";
  c.file = t.file();
  for (const char* k : {"key", "excite", "midi", "osc"})
    if (const toml::node* n = t.node(k)) {
      c.line = static_cast<int>(n->source().begin.line);
      c.column = static_cast<int>(n->source().begin.column);
      break;
    }
  read_midi(t, c);
  if (t.has("osc")) read_key(t, c, control_keys(), "osc");
  if (c.midi == audio::MidiSource::none && c.osc.empty())
    t.fail("midi", "a control needs a source: 'midi', 'osc' or both");
  if (t.has("key")) {
    read_key(t, c, control_keys(), "key");
    const toml::node* r = t.node("range");
    const toml::array* a = r ? r->as_array() : nullptr;
    if (!a || a->size() != 2 || !(*a)[0].is_number() || !(*a)[1].is_number())
      t.fail("range", "is required with 'key': two numbers, range = [low, high]");
    c.low = *(*a)[0].value<double>();
    c.high = *(*a)[1].value<double>();
    if (!std::isfinite(c.low) || !std::isfinite(c.high) || c.low == c.high)
      t.fail("range", "must be two different finite numbers");
    read_key(t, c, control_keys(), "smooth");
  } else {
    if (t.has("range")) t.fail("range", "maps a value onto 'key': give 'key' too");
    if (t.has("smooth")) t.fail("smooth", "glides a 'key': give 'key' too");
  }
  if (auto e = t.table("excite")) c.excite = excitation(*e, m);
  if (c.key.empty() && !c.excite)
    t.fail("key", "a control needs 'key' (a parameter to change) or 'excite' (a strike)");
  t.finish();
  return c;
}

}  // namespace

std::vector<audio::Control> read_control_tables(TomlCursor& top, const Model& m) {
  std::vector<audio::Control> controls;
  for (auto& t : top.tables("control")) controls.push_back(control(t, m, controls.size()));
  return controls;
}

}  // namespace maille
