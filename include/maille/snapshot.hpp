// What the physics hands to whoever draws or writes frames: positions and when they were taken.
// The renderer and the frame writers see only this (plus the model's static topology).
#pragma once

#include <array>
#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "maille/mat3.hpp"
#include "maille/mesh.hpp"
#include "maille/vec3.hpp"

namespace maille {

// A segment drawn on top of the scene: ends in metres, colour as RGB in [0, 1].
struct OverlaySegment {
  Vec3 a, b;
  std::array<float, 3> colour{1, 1, 0};
};

// A solid drawn with the scene (obstacles): a mesh shared with the stage that owns it, placed
// by x_world = direct x + translation at the time of the snapshot. The mesh never changes
// between snapshots of one stage, so renderers may upload it once per pointer.
struct SurfaceInstance {
  std::string name;                     // the stage's, e.g. "obstacle:table"
  std::shared_ptr<const TriMesh> mesh;  // counter-clockwise seen from outside
  Mat3 direct = Mat3::identity();
  Vec3 translation{};
  std::array<float, 4> colour{0.55f, 0.6f, 0.7f, 0.45f};  // RGBA: translucent by default
};

// Positions left on the device (Simulator::set_device_snapshots): an OpenGL buffer object of 3
// floats per point, in the share group of the context the backend runs in. Who receives it
// reads it in that share group, with its own synchronisation (render::SnapshotExchange fences
// it across threads); the simulator's buffer is valid only during the listener's call.
struct DevicePositions {
  std::uint32_t gl_buffer = 0;  // 0: none (the positions are on the host)
  std::size_t count = 0;        // points
};

struct Snapshot {
  std::uint64_t frame = 0;      // 0, 1, 2, ... one per publication
  std::uint64_t step = 0;       // simulation step of the positions
  double time = 0;              // s
  std::vector<Vec3> positions;  // empty when `device` holds them
  DevicePositions device;
  // What stages chose to show (self-collision contacts and cells...), only when the simulator
  // was asked for overlays (Simulator::set_overlays): empty otherwise, and free.
  std::vector<OverlaySegment> overlay;
  // Solids placed at the snapshot's time (always filled: obstacles are part of the scene).
  std::vector<SurfaceInstance> surfaces;

  std::size_t point_count() const { return device.gl_buffer ? device.count : positions.size(); }
};

using SnapshotListener = std::function<void(const Snapshot&)>;

}  // namespace maille
