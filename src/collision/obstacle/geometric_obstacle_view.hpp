// What device backends that run the geometric obstacle stage themselves (the GPU's kernels,
// src/gpu/gpu_obstacle.hpp) read of it. Private to the engine: not part of the public API.
#pragma once

#include <cstdint>
#include <span>

#include "maille/obstacle.hpp"

namespace maille {

// The geometric obstacle a stage runs. `obstacle` is null when `st` is not the stage of an
// obstacle with method = "geometric". Valid while the stage lives.
struct GeometricObstacleView {
  const Obstacle* obstacle = nullptr;
  std::span<const std::uint32_t> points;  // the colliding points, increasing
  // The cull: points farther than this from the placement's translation touch nothing, m
  // (+inf for the plane).
  Real reach = 0;
  // The stage's PointContacts::thickness() (the thinnest contact region, m; +inf: a plane).
  Real thickness = 0;
};
GeometricObstacleView geometric_obstacle_view(const Stage& st);

}  // namespace maille
