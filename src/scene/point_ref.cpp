#include "point_ref.hpp"

#include <limits>
#include <stdexcept>

namespace maille {

namespace {

// The index after "group:", or -1 when it is not a whole number.
long long index_after_colon(const std::string& ref, std::size_t colon) {
  std::size_t used = 0;
  long long i = -1;
  try {
    i = std::stoll(ref.substr(colon + 1), &used);
  } catch (const std::exception&) {
    return -1;
  }
  return used == ref.size() - colon - 1 ? i : -1;
}

}  // namespace

std::uint32_t point_ref(SceneTable& t, std::string_view key, const Model& m, std::string* label,
                        std::string (*group_advice)(const std::string& name)) {
  if (!t.has(key)) t.fail(key, "is required but missing");
  if (t.has_integer(key)) {
    constexpr auto most = std::numeric_limits<std::int64_t>::max();
    const std::int64_t i = t.integer(key, 0, -most, most);
    if (i < 0 || i >= std::int64_t(m.points.size()))
      t.fail(key, "point index " + std::to_string(i) + " does not exist (the scene has " +
                      std::to_string(m.points.size()) + " points)");
    if (label) *label = std::to_string(i);
    return static_cast<std::uint32_t>(i);
  }
  if (!t.has_text(key)) t.fail(key, "must be a point name, \"group:index\" or an index");
  const std::string ref = t.text(key, "");
  if (label) *label = ref;
  const auto colon = ref.find(':');
  const Group* g = m.group(ref.substr(0, colon));
  if (!g) t.fail(key, "no point or group named '" + ref.substr(0, colon) + "'");
  if (colon == std::string::npos) {
    if (g->count != 1)
      t.fail(key, group_advice ? "'" + ref + "' is a group of " + std::to_string(g->count) +
                                     " points: " + group_advice(ref)
                               : "'" + ref + "' is a group: use '" + ref + ":index'");
    return g->first;
  }
  const long long i = index_after_colon(ref, colon);
  if (i < 0 || i >= g->count)
    t.fail(key, "'" + ref + "': index must be in [0, " + std::to_string(g->count - 1) + "]");
  return g->first + static_cast<std::uint32_t>(i);
}

}  // namespace maille
