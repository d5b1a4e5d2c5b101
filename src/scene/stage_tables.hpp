// The built-in stage tables' parsers, one file each, registered in stage_registry.cpp.
#pragma once

#include <optional>
#include <span>

#include "maille/model.hpp"
#include "maille/scene_table.hpp"
#include "maille/stage.hpp"

namespace maille {

StageSpec obstacle_table(SceneTable& t, const Model& m);  // [[obstacle]]: obstacle_table.cpp
// [[contact]], every table at once (contact_table.cpp): links added to `m`, and the broad-phase
// tables' one stage.
std::optional<StageSpec> contact_tables(std::span<SceneTable* const> tables, Model& m);
// [[link]] kind = "geometric_contact", every such table at once (geometric_contact_table.cpp).
std::optional<StageSpec> geometric_contact_links(std::span<SceneTable* const> tables, Model& m);

}  // namespace maille
