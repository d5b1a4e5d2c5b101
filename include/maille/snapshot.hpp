// What the physics hands to whoever draws or writes frames: positions and when they were taken.
// The renderer and the frame writers see only this (plus the model's static topology).
#pragma once

#include <cstdint>
#include <functional>
#include <vector>

#include "maille/vec3.hpp"

namespace maille {

struct Snapshot {
  std::uint64_t frame = 0;  // 0, 1, 2, ... one per publication
  std::uint64_t step = 0;   // simulation step of the positions
  double time = 0;          // s
  std::vector<Vec3> positions;
};

using SnapshotListener = std::function<void(const Snapshot&)>;

}  // namespace maille
