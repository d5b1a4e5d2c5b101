// The builders' keys ([[flag]], [[rope]], ...), declared once (stage_keys.hpp): builder_tables.cpp
// reads each table through them and docs/scene-format.md's tables are generated from them.
// `name` and `drive`, common to every builder, are read by the scene reader (scene_keys.hpp).
#pragma once

#include <span>

#include "maille/builders.hpp"
#include "maille/stage_keys.hpp"

namespace maille {

std::span<const StageKey<FlagParams>> flag_keys();
std::span<const StageKey<RopeParams>> rope_keys();
std::span<const StageKey<NetParams>> net_keys();
std::span<const StageKey<MembraneParams>> membrane_keys();
std::span<const StageKey<LatticeParams>> lattice_keys();
std::span<const StageKey<FloorParams>> floor_keys();

}  // namespace maille
