// What device backends that run the self-collision stage themselves (the GPU's uniform grid,
// src/gpu/gpu_self_collision.cpp) read of it. Private to the engine: not part of the public API.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "maille/self_collision.hpp"

namespace maille {

// What a self-collision stage runs now. `settings` is null when `st` is not a self-collision
// stage; otherwise it holds the live options (exclusion, broad phase) and the resolved radius
// (> 0). The view is valid until the stage's next model_changed.
struct SelfCollisionView {
  const SelfCollisionSettings* settings = nullptr;
  bool enabled = false;                      // the live option "enabled"
  std::span<const std::uint32_t> particles;  // the colliding points: the groups' free points
};
SelfCollisionView self_collision_view(const Stage& st);

// The pairs the topological exclusion removes, as rows (CSR over local indices: positions in
// `particles`), whatever the stage's exclusion mode: the matrix form, which removes exactly the
// pairs the signature form removes (test unit.SelfCollision.ExclusionRemovesExactly...).
// `particles` sorted; radius 0: empty rows.
struct ExclusionRows {
  std::vector<std::uint32_t> offset;   // [particles + 1]: row a is [offset[a], offset[a + 1])
  std::vector<std::uint32_t> partner;  // local indices, sorted in each row
};
ExclusionRows self_collision_exclusion_rows(const Model& m,
                                            std::span<const std::uint32_t> particles,
                                            int topological_radius);

}  // namespace maille
