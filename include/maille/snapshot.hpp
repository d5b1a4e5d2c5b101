// What the physics hands to whoever draws or writes frames: positions and when they were taken.
// The renderer and the frame writers see only this (plus the model's static topology).
#pragma once

#include <array>
#include <cstdint>
#include <functional>
#include <vector>

#include "maille/vec3.hpp"

namespace maille {

// A segment drawn on top of the scene: ends in metres, colour as RGB in [0, 1].
struct OverlaySegment {
  Vec3 a, b;
  std::array<float, 3> colour{1, 1, 0};
};

struct Snapshot {
  std::uint64_t frame = 0;  // 0, 1, 2, ... one per publication
  std::uint64_t step = 0;   // simulation step of the positions
  double time = 0;          // s
  std::vector<Vec3> positions;
  // What stages chose to show (self-collision contacts and cells...), only when the simulator
  // was asked for overlays (Simulator::set_overlays): empty otherwise, and free.
  std::vector<OverlaySegment> overlay;
};

using SnapshotListener = std::function<void(const Snapshot&)>;

}  // namespace maille
