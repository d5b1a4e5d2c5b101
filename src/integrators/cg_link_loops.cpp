// Conjugate gradients' loops over a pool's links (maille/link_loops.hpp): the per-link blocks
// C_l = h df/dv + h^2 df/dx of the linearised step, their product with a vector, and the
// block-Jacobi diagonal. The kind gives its Jacobians per batch; the blocks, right-hand side and
// products are kind-agnostic.
#include <algorithm>

#include "../core/schedule_loops.hpp"
#include "maille/link_loops.hpp"

namespace maille {

void implicit_blocks(const LinkPoolBase& pool, const Vec3* x, const Vec3* v, Real h, Mat3* blocks,
                     Vec3* rhs) {
  if (!pool.has_jacobian()) return;
  const LinkEnds* ends = pool.slot_ends().data();
  detail::for_each_range(pool, [&](std::size_t begin, std::size_t end) {
    constexpr std::size_t kBatch = 64;
    LinkJacobian j[kBatch];
    for (std::size_t first = begin; first < end; first += kBatch) {
      const std::size_t n = std::min(kBatch, end - first);
      pool.jacobians(first, n, x, v, j);
      for (std::size_t k = 0; k < n; ++k) {
        const std::size_t l = first + k;
        blocks[l] = j[k].dv * h + j[k].dx * (h * h);
        if (!rhs) continue;
        const auto [a, b] = ends[l];
        const Vec3 r = (j[k].dx * (v[b] - v[a])) * (h * h);
        rhs[a] += r;
        rhs[b] -= r;
      }
    }
  });
}

void apply_blocks(const LinkPoolBase& pool, const Mat3* blocks, const Vec3* u, Vec3* out) {
  if (!pool.has_jacobian()) return;
  const LinkEnds* ends = pool.slot_ends().data();
  detail::for_each_range(pool, [&](std::size_t begin, std::size_t end) {
    for (std::size_t l = begin; l < end; ++l) {
      const auto [a, b] = ends[l];
      const Vec3 w = blocks[l] * (u[b] - u[a]);
      out[a] -= w;
      out[b] += w;
    }
  });
}

void add_block_diagonal(const LinkPoolBase& pool, const Mat3* blocks, Mat3* diagonal) {
  const auto ends = pool.slot_ends();
  for (std::size_t l = 0; l < ends.size(); ++l) {
    diagonal[ends[l].a] += blocks[l];
    diagonal[ends[l].b] += blocks[l];
  }
}

}  // namespace maille
