// Internal: the contact set's obstacles as the CG solvers' matrix sees them (matrix_free and
// eigen share it): per free point, h^2 K + h D on its own diagonal block, and the right-hand
// side's h^2 df/dx v = -h^2 K v (K alone: the terms with 1/h = 0). The obstacles are placed at
// the state's time for the blocks, then at t + h for the rest of the solve.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "maille/contact_set.hpp"
#include "maille/mat3.hpp"
#include "maille/state.hpp"

namespace maille {

struct ObstacleBlocks {
  std::vector<Mat3> blocks;     // [points] h^2 K + h D
  std::vector<Mat3> stiffness;  // [points] K (scratch)
  std::vector<Vec3> sink;       // [points] their forces, discarded
  // Fills `blocks` (and subtracts h^2 K v from rhs when rhs is not null); false, blocks
  // untouched, when there is no obstacle.
  bool take(std::span<PointContacts* const> obstacles, const State& s, Real h,
            std::span<const std::uint32_t> free, Vec3* rhs);
};

}  // namespace maille
