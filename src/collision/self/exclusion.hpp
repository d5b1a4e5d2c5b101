// Topological exclusion: particles at graph distance <= R links (through every always-active
// link of the model, conditional contacts excluded) never collide with each other.
//
// Two representations answer the same question:
//   matrix     per particle, the sorted local indices of the particles within R: a compact form
//              of the boolean matrix B (n * ~40 entries for grid cloth at R = 2, where a dense
//              bit matrix would need n^2 / 8 bytes: 512 MiB at n = 64k)
//   signature  for grid groups (flag, net): a stencil of index offsets (di, dj) within R,
//              measured by a breadth-first search from the grid's centre and checked at its
//              corners and edges; cells carry the (i, j) box of their particles (CellSignature)
//              and a cell pair whose box spans at most `full_span` indices is skipped whole.
//              Particles of other groups fall back to the matrix.
#pragma once

#include <cstdint>
#include <vector>

#include "maille/model.hpp"

namespace maille::collision {

// The (i, j) box of a cell's particles in their grid group; group -1: mixed, not a grid, empty.
struct CellSignature {
  std::int32_t group = -2;  // -2: empty
  std::int32_t i0 = 0, i1 = 0, j0 = 0, j1 = 0;
  void add(std::int32_t g, std::int32_t i, std::int32_t j);
  void merge(const CellSignature& o);
};

class TopologicalExclusion {
 public:
  // `set`: global point ids of the colliding particles (sorted). With radius 0 nothing is
  // excluded. `signature`: build stencils for grid groups (others still get matrix rows).
  TopologicalExclusion(const Model& m, const std::vector<std::uint32_t>& set, int radius,
                       bool signature);

  // Local indices a, b (positions in `set`).
  bool excluded(std::uint32_t a, std::uint32_t b) const {
    if (radius_ == 0) return false;
    const Grid& ga = grid_of_[a];
    if (ga.group >= 0 && ga.group == grid_of_[b].group) return in_stencil(ga, grid_of_[b]);
    // Other pairs (another group, or no stencil): the rows.
    return matrix_excluded(a, b);
  }
  bool matrix_excluded(std::uint32_t a, std::uint32_t b) const;
  int radius() const { return radius_; }
  // Whether every pair inside the union of two cells is excluded.
  bool all_excluded(const CellSignature& s) const {
    return radius_ > 0 && s.group >= 0 && s.i1 - s.i0 <= full_span_[std::size_t(s.group)] &&
           s.j1 - s.j0 <= full_span_[std::size_t(s.group)];
  }
  // Adds particle a to a cell's signature.
  void sign(CellSignature& s, std::uint32_t a) const {
    const Grid& g = grid_of_[a];
    s.add(g.group, g.i, g.j);
  }
  std::size_t bytes() const;
  // The longest matrix row among up to 64 particles spread over `set` (a bounded search from
  // each): rows are about that long inside a cloth, shorter at its edges. What the memory
  // estimate and the rows' reservation use (on grid cloth a row is not (2R + 1)^2 long: bending
  // links reach two points a hop, about (4R + 1)^2 / 2 in all).
  static std::uint64_t sampled_row_bound(const Model& m, const std::vector<std::uint32_t>& set,
                                         int radius);
  std::size_t matrix_entries() const { return neighbours_.size(); }
  // The matrix rows (CSR over local indices; without signatures, every particle's full row).
  const std::vector<std::uint32_t>& row_offsets() const { return offsets_; }
  const std::vector<std::uint32_t>& row_entries() const { return neighbours_; }
  bool uses_signature() const { return signature_; }

 private:
  struct Grid {
    std::int32_t group = -1;  // stencil index, -1: not a grid particle (matrix rows)
    std::int32_t i = 0, j = 0;
  };
  struct Stencil {
    std::int32_t reach = 0;          // |di|, |dj| <= reach
    std::vector<std::uint8_t> bits;  // (2 reach + 1)^2, 1: within R
  };
  bool in_stencil(const Grid& a, const Grid& b) const {
    const Stencil& s = stencils_[std::size_t(a.group)];
    const std::int32_t di = b.i - a.i, dj = b.j - a.j;
    if (di < -s.reach || di > s.reach || dj < -s.reach || dj > s.reach) return false;
    const std::int32_t w = 2 * s.reach + 1;
    return s.bits[std::size_t((dj + s.reach) * w + di + s.reach)] != 0;
  }

  int radius_ = 0;
  bool signature_ = false;
  std::vector<Grid> grid_of_;              // [set]
  std::vector<Stencil> stencils_;          // per grid group
  std::vector<std::int32_t> full_span_;    // per grid group
  std::vector<std::uint32_t> offsets_;     // [set + 1] matrix rows (CSR)
  std::vector<std::uint32_t> neighbours_;  // local indices, sorted per row
};

}  // namespace maille::collision
