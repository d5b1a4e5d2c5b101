// The built-in stage tables' parsers, one file each, registered in stage_registry.cpp.
#pragma once

#include "maille/model.hpp"
#include "maille/scene_table.hpp"
#include "maille/stage.hpp"

namespace maille {

StageSpec obstacle_table(SceneTable& t, const Model& m);  // [[obstacle]]: obstacle_table.cpp

}  // namespace maille
