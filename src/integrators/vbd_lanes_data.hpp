// Internal: the plain data the lanes kernels of vertex block descent read (vbd_lanes_kernel.hpp)
// and the table of one width's kernels. No inline functions: the kernels' translation units are
// compiled for other instruction sets than the rest of the program.
#pragma once

#include <cstddef>
#include <cstdint>

#include "maille/vec3.hpp"

namespace maille::vbd_lanes {

// The padded adjacency of the lane pools: rows of W lanes, a row per link rank of a block's
// points (the k-th link of each lane's point), W neighbour indices and 3 W parameters
// (stiffness, rest length, damping; a padding lane links its point to itself with zeros).
struct Rows {
  const std::uint32_t* neighbour;  // [rows * W]
  const Real* params;              // [rows * 3 W]: k[W], rest[W], damping[W]
};

// One block: W points of a colour (a partial block repeats its first point in the lanes past
// `lanes`), its rows from first_row, depth[q] rows for lane pool q, has[q] the lanes whose point
// has a link in pool q.
struct Block {
  const std::uint32_t* points;  // [W]
  std::uint32_t lanes;          // real points
  std::uint32_t first_row;
  std::uint32_t pools;
  const std::uint32_t* depth;  // [pools]
  const std::uint8_t* has;     // [pools], bit l for lane l
};

// The step's arrays (Vec3 and Mat3 viewed as 3 and 9 Reals) and constants.
struct Step {
  const Real* x;
  const Real* v;
  const Real* y;
  const Real* mass;
  Real inv_h, inv_h2, drag;
};

// One width's kernels (vbd_lanes_kernel.hpp).
struct Kernels {
  int width;
  // g and H of a block's points: inertia, drag and the lane pools, written to g (3 per point)
  // and h (9 per point).
  void (*terms)(const Block& b, const Rows& rows, const Step& s, Real* g, Real* h);
  // dx = H^-1 g of a block's points into out[3 l + c].
  void (*solve)(const std::uint32_t* points, std::uint32_t lanes, const Real* g, const Real* h,
                Real* out);
};

}  // namespace maille::vbd_lanes
