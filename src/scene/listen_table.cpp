// [[listen]]: one channel each. The point is `point` (a [[mass]] or [[fixed]] name, "group:index"
// or a global index) or `group` with `index`; `quantity` is position, velocity or force, read
// along `axis`. [audio]: the rate, the sample format, the gain and the resampler.
#include "listen_table.hpp"

#include "audio_keys.hpp"
#include "point_ref.hpp"

#include <string>

namespace maille {

// The point a listener names, checked like a link's ends.
std::uint32_t listened_point(TomlCursor& t, const Model& m, std::string& label) {
  const bool by_point = t.has("point"), by_group = t.has("group") || t.has("index");
  if (by_point && by_group)
    t.fail(t.has("group") ? "group" : "index",
           "give either 'point' or 'group' with 'index', not both");
  if (!by_point && !by_group)
    t.fail("point",
           "is required: a point name, \"group:index\", a point index, or 'group' "
           "with 'index'");
  if (by_group) {
    const std::string name = t.text("group");
    const Group* g = m.group(name);
    if (!g) t.fail("group", "no group named '" + name + "'");
    const std::int64_t count = g->count;
    if (!t.has("index"))
      t.fail("index", "is required with 'group' (0 to " + std::to_string(count - 1) + ")");
    const std::int64_t i = t.integer("index", 0, 0, count - 1);
    label = name + ":" + std::to_string(i);
    return g->first + static_cast<std::uint32_t>(i);
  }
  return point_ref(t, "point", m, &label, [](const std::string& name) {
    return "use '" + name + ":index' or group = \"" + name + "\" with index";
  });
}

namespace {

audio::Listener listener(TomlCursor& t, const Model& m) {
  audio::Listener l;
  l.point = listened_point(t, m, l.label);
  read_keys(t, l, listen_keys());  // quantity, axis (audio_keys.cpp)
  l.axis = l.axis / norm(l.axis);
  t.finish();
  return l;
}

}  // namespace

audio::AudioSpec read_audio_tables(TomlCursor& top, const Model& m) {
  audio::AudioSpec spec;
  for (auto& t : top.tables("listen")) spec.listeners.push_back(listener(t, m));
  if (auto t = top.table("audio")) {
    audio::AudioSettings& s = spec.settings;
    read_keys(*t, s, audio_keys());  // the keys: audio_keys.cpp
    if (spec.listeners.empty())
      t->fail("", "an [audio] table needs at least one [[listen]] table (its channels)");
    t->finish();
  }
  spec.controls = read_control_tables(top, m);
  if (!spec.controls.empty() && spec.listeners.empty())
    top.fail("control", "[[control]] tables play a model's [[listen]] channels: add one");
  if (spec.listeners.size() > 64)
    top.fail("listen", "at most 64 [[listen]] tables (channels), got " +
                           std::to_string(spec.listeners.size()));
  return spec;
}

}  // namespace maille
