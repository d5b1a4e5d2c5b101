// Internal: the coarse correction of vertex block descent (implicit_vbd.cpp): a two-level scheme
// whose coarse space makes VBD's convergence independent of the cloth's resolution.
//
// Why: a VBD sweep is block Gauss-Seidel. It removes an error whose wavelength is a few links in
// one sweep, but an error spread over the whole cloth (the sag of a cloth draped on a sphere)
// falls by about 1 - c / n^2 per sweep on an n x n grid, and k h^2 / m grows as n^2 at a fixed
// cloth: at 1/60 s with 10 sweeps a 32^2 cloth on a sphere stretched 21 %, 64^2 108 % and 128^2
// 3016 % (docs/implicit.md). The coarse space takes that smooth error out in one linear solve.
//
// How (aggregation, as in algebraic multigrid: Vanek, Mandel and Brezina 1996):
//   aggregates  the free points cut into connected groups over the always-active links (a point
//               and its neighbours, then the rest joined to a neighbouring group), once per model
//   P0          the tentative prolongation: a coarse unknown e_A moves every point of A by e_A
//   H_c         = P0^T H P0, H the step's Hessian of G (implicit_vbd.hpp) with the diagonal blocks
//               of the sweeps (mass, links, contacts) and the always-active links' off-diagonal
//               blocks; contact links and point-triangle contacts stay on the diagonal (as if
//               anchored: they only make the correction smaller). A link inside an aggregate
//               cancels (a rigid shift does not stretch it). Factorised at each correction
//               (Eigen's simplicial LDL^T; the fill-reducing order and the symbolic analysis
//               once per model: CHOLMOD's supernodal Cholesky was measured slower on these
//               matrices, docs/implicit.md)
//   direction   e = H_c^-1 P0^T g, p = (I - w D^-1 H) P0 e (the prolongation smoothed once, as in
//               smoothed aggregation: P0 e jumps between aggregates, and a jump stretches the
//               links that cross it, so P0^T H P0 is about an aggregate's width too stiff for
//               smooth errors), then the step along p that minimises the quadratic model:
//               alpha = g.p / p.H p
#pragma once

#include <cstdint>
#include <memory>
#include <span>
#include <vector>

#include "maille/mat3.hpp"
#include "maille/model.hpp"

namespace maille {

class CoarseCorrection {
 public:
  CoarseCorrection();
  ~CoarseCorrection();
  CoarseCorrection(CoarseCorrection&&) noexcept;
  CoarseCorrection& operator=(CoarseCorrection&&) noexcept;

  // Aggregates the free points (increasing) over the model's always-active pools with a
  // Jacobian, and analyses the coarse matrix's pattern. Once per model (allocates).
  void build(const Model& m, std::span<const std::uint32_t> free, std::size_t points);
  void reset();
  std::size_t aggregates() const;

  // Where the caller writes the blocks J_x + J_v / h of `pool`'s links (storage order) before
  // prepare(), or null when the correction does not keep that pool (conditional, no Jacobian).
  Mat3* blocks_of(const LinkPoolBase* pool);
  // The coarse matrix from the kept links' blocks (blocks_of) and the points' diagonal blocks
  // `diag` (the sweeps' H_i). False when it is not positive definite (no
  // correction this time).
  bool prepare(const Mat3* diag);
  // prepare()'s numeric factorisation alone, of the matrix it last assembled (benchmarks).
  bool factorise();
  // That matrix (3 rows per aggregate, in the fill-reducing order): its upper triangle in
  // compressed columns, for a benchmark to factorise it by other means (bench_coarse_factor.cpp).
  struct Matrix {
    int n = 0;
    const int* column_start = nullptr;  // [n + 1]
    const int* rows = nullptr;          // sorted within a column
    const double* values = nullptr;
  };
  Matrix matrix() const;
  // The direction p (free points; 0 elsewhere) for the gradient g = -dG/dx, with its step
  // length: x + alpha p minimises the quadratic model (the Hessian prepared) along p. Returns
  // alpha (0: none). Needs prepare() in this step; allocates nothing.
  Real direction(const Vec3* g, Vec3* p);

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace maille
