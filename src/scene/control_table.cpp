// [[control]]: a MIDI and/or OSC source mapped onto a scene key or an excitation (`maille play`,
// docs/sound.md "Controls"). What can be checked from the file is checked here; whether the key
// may change while the model plays is checked when playing starts (control_keys.cpp), since it
// needs the scene read again.
#include <string>

#include "audio_keys.hpp"
#include "listen_table.hpp"

namespace maille {

namespace {

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
  read_keys(e, x, excite_keys());  // quantity, axis, amount (audio_keys.cpp)
  x.axis = x.axis / norm(x.axis);
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
  // The keys are declared in control_keys() (audio_keys.cpp), read in this order: a source,
  // then what it changes (range and smooth only with a key).
  const auto keys = control_keys();
  read_key(t, c, keys, "midi");
  read_key(t, c, keys, "midi_channel");
  if (t.has("osc")) read_key(t, c, keys, "osc");
  if (c.midi == audio::MidiSource::none && c.osc.empty())
    t.fail("midi", "a control needs a source: 'midi', 'osc' or both");
  if (t.has("key")) read_key(t, c, keys, "key");
  read_key(t, c, keys, "range");
  read_key(t, c, keys, "smooth");
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
