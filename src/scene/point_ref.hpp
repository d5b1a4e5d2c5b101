// The point a scene key names, read the one way every table reads it ([[link]] a and b, a
// geometric contact's b, [[listen]] and [[control]] excite's point).
#pragma once

#include <cstdint>
#include <string>
#include <string_view>

#include "maille/model.hpp"
#include "maille/scene_table.hpp"

namespace maille {

// `key` as a point: a [[mass]] or [[fixed]] name (a group of one point), "group:index" or a
// global index; fails at the key otherwise. `label` (when given) receives the reference as
// written. A group of several points is refused with "'name' is a group of N points: " and
// group_advice(name), or by default "'name' is a group: use 'name:index'".
std::uint32_t point_ref(SceneTable& t, std::string_view key, const Model& m,
                        std::string* label = nullptr,
                        std::string (*group_advice)(const std::string& name) = nullptr);

}  // namespace maille
