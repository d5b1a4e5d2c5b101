// The loops that run a pool's links, whatever its kind, one per solver that owns it. Each reads
// the pool's storage and schedule (link_pool.hpp) and calls the kind's law over batches of links
// (one virtual call per batch, never per link); the bodies live with their solvers:
//   forces (every scheme)          src/core/link_loops.cpp
//   conjugate gradients' blocks    src/integrators/cg_link_loops.cpp
//   vertex block descent's terms   src/integrators/vbd_link_loops.cpp
// Functions marked "team" may be called inside an OpenMP parallel region by every thread of the
// team (the threads split each colour of the schedule) or outside one (serially, same order).
#pragma once

#include <cstdint>
#include <span>

#include "maille/link_pool.hpp"

namespace maille {

// ---- Forces ----
// Team: adds every link's force into f; counts the active links of conditional kinds.
void accumulate_forces(const LinkPoolBase& pool, const Vec3* x, const Vec3* v, Vec3* f,
                       LinkCounters& counters);
// Team: the structured kernel alone (detail/structured_grid.hpp): adds its links' forces into f,
// or, with a hook, writes the grid points' f (not read) and calls the hook on each finished row
// (the fused step).
void structured_forces(const LinkPoolBase& pool, const Vec3* x, const Vec3* v, Vec3* f,
                       const detail::StructuredGrid::RowHook* hook);
// Team: the general schedule's links alone (those off the structured kernel).
void other_forces(const LinkPoolBase& pool, const Vec3* x, const Vec3* v, Vec3* f);

// ---- Conjugate gradients (Baraff-Witkin) ----
// Team: for every link l (storage order): C_l = h dv + h^2 dx (definite mode) into blocks[l],
// and, when rhs is not null, the right-hand side term h^2 (df/dx v): rhs_a += h^2 dx (v_b - v_a),
// rhs_b -= it. Kinds without a Jacobian add nothing.
void implicit_blocks(const LinkPoolBase& pool, const Vec3* x, const Vec3* v, Real h, Mat3* blocks,
                     Vec3* rhs);
// Team: out -= (h df/dv + h^2 df/dx) u, link by link: w = C_l (u_b - u_a); out_a -= w; out_b += w.
void apply_blocks(const LinkPoolBase& pool, const Mat3* blocks, const Vec3* u, Vec3* out);
// Serial: adds every C_l to the diagonal blocks of its two points (block-Jacobi preconditioner).
void add_block_diagonal(const LinkPoolBase& pool, const Mat3* blocks, Mat3* diagonal);

// ---- Vertex block descent (src/integrators/implicit_vbd.cpp) ----
// For each point i of `points`, the links of this pool at i are the storage slots
// slots[row[i]] .. slots[row[i + 1] - 1]: adds their forces on i into f[i] and the block
// -d f_i / d x_i into hessian[i], with velocities that follow positions as in implicit Euler
// (v = (x - x_n) / h, hence J_x + J_v / h), definite-mode Jacobians (the block stays positive
// semi-definite). Inactive conditional links add nothing. Points are independent: threads may
// run disjoint point sets at once.
void add_point_terms(const LinkPoolBase& pool, std::span<const std::uint32_t> points,
                     const std::uint32_t* row, const std::uint32_t* slots, const Vec3* x,
                     const Vec3* v, Real inv_h, Vec3* f, Mat3* hessian);
// Serial: the same terms link by link (VBD's coarse correction, vbd_coarse.hpp): every link once,
// in storage order, its force into f[a] (f[b] gets the opposite), its block into hessian[a],
// hessian[b] and blocks[l] (zero for an inactive conditional link). One evaluation per link where
// add_point_terms makes two.
void add_link_terms(const LinkPoolBase& pool, const Vec3* x, const Vec3* v, Real inv_h, Vec3* f,
                    Mat3* hessian, Mat3* blocks);

}  // namespace maille
