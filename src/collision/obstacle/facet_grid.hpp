// The facets of a mesh obstacle in the mesh's own frame, with what the inverse-dynamics stage
// asks of them per particle: which facets are near a segment (a uniform grid of the facets'
// boxes), where a segment first crosses a facet (the ray-facet test), and the closest
// surface point with a reliable inside/outside sign (angle-weighted pseudo-normals, Baerentzen
// and Aanaes 2005) for the leak check. Built once; obstacles move by moving the particles into
// this frame, never by refitting.
#pragma once

#include <algorithm>
#include <array>
#include <cstdint>
#include <limits>
#include <span>
#include <vector>

#include "maille/mesh.hpp"

namespace maille::facets {

// Barycentric tolerance: a point this close (relative to the facet) to a shared edge counts as
// inside both facets, so a crossing exactly on a joint is never lost to rounding (the hit then
// goes to the earliest, or the first, of them: either one stops the particle).
inline constexpr Real kInsideTolerance = Real(1e-9);

// What every query reads (128 bytes): kept apart from the pseudo-normals, which only the rare
// inside check reads, so the facets near a cloth stay in cache.
struct Facet {
  Vec3 a;       // vertex a
  Vec3 n;       // unit normal (e1 x e2 normalised): the outside
  Vec3 e1, e2;  // edges b - a, c - a
  // Barycentric solve of a point on the plane: precomputed Gram entries.
  Real d00, d01, d11, inv_det;
};

struct PseudoNormals {
  std::array<Vec3, 3> vertex;  // angle-weighted normals at a, b, c
  std::array<Vec3, 3> edge;    // sum of the two faces' normals on ab, bc, ca
};

struct Hit {
  std::uint32_t facet = 0;
  Real u = 2;  // fraction of the segment where it crosses the facet's plane
};

struct Closest {
  std::uint32_t facet = 0;
  Vec3 point;
  Real distance2 = 0;
  Real sign = 1;  // +1 outside, -1 inside (by the pseudo-normal of the closest feature)
};

class FacetGrid {
 public:
  explicit FacetGrid(const TriMesh& mesh);

  const std::vector<Facet>& facets() const { return facets_; }
  bool closed() const { return closed_; }
  const Vec3& lo() const { return lo_; }  // the grid's box
  const Vec3& hi() const { return hi_; }
  // Facets whose boxes may meet the box [lo, hi] (a facet may repeat): empty when the box
  // misses the grid; else gathered into `scratch`, which the result views. `row` is the
  // caller's memory of the single cell its last query fell in and of that cell's facets: a
  // query in the same cell again (a settled cloth, most steps) reads them from there, in the
  // caller's sequential memory, rather than from the grid (cache misses over a large mesh).
  // A query box inside the row's `inner` box is in that cell, found with six comparisons.
  static constexpr std::uint64_t kNoCell = ~std::uint64_t(0);
  struct Row {
    std::uint64_t cell = kNoCell;
    std::uint32_t begin = 0, end = 0;    // the row in the grid
    std::array<std::uint32_t, 6> ids{};  // a copy of it when it is that short
    bool in_cell = false;  // the last query fell in this one cell (its result is the row)
    // Points that cell_of puts in `cell` (and inside the grid's box): empty until a cell is set.
    Vec3 inner_lo{Vec3{1, 1, 1} * std::numeric_limits<Real>::infinity()};
    Vec3 inner_hi{Vec3{1, 1, 1} * -std::numeric_limits<Real>::infinity()};
  };
  std::span<const std::uint32_t> candidates(const Vec3& lo, const Vec3& hi,
                                            std::vector<std::uint32_t>& scratch, Row& row) const {
    if (lo.x >= row.inner_lo.x && lo.y >= row.inner_lo.y && lo.z >= row.inner_lo.z &&
        hi.x <= row.inner_hi.x && hi.y <= row.inner_hi.y && hi.z <= row.inner_hi.z) {
      row.in_cell = true;  // what the test below finds, without it
      return row_facets(row);
    }
    if (facets_.empty()) return {};
    for (int d = 0; d < 3; ++d)
      if (!(hi[d] >= lo_[d] && lo[d] <= hi_[d])) return {};  // NaN misses too
    const auto c0 = cell_of(lo), c1 = cell_of(hi);
    row.in_cell = c0 == c1;
    if (!row.in_cell) return candidates_in_cells(c0, c1, scratch);
    const std::uint64_t c = cell_index(c0[0], c0[1], c0[2]);
    if (c != row.cell) {
      row.cell = c, row.begin = starts_[c], row.end = starts_[c + 1];
      if (row.end - row.begin <= row.ids.size())
        std::copy(entries_.begin() + row.begin, entries_.begin() + row.end, row.ids.begin());
      inner_box(c0, row);
    }
    return row_facets(row);
  }

  // The ray-facet test of the segment p -> q against facet f, with `eps` the "above" threshold
  // in this frame: N.AP > eps, N.PQ < 0, u <= 1 and M inside the facet (closed edges, with a
  // relative tolerance so that a crossing on a shared edge is found by both facets).
  // Inlined (as are the two below): the stage calls them a few times per particle.
  bool crosses(std::uint32_t f, const Vec3& p, const Vec3& q, Real eps, Real& u) const {
    return crosses_above(f, dot(facets_[f].n, p - facets_[f].a), p, q, eps, u);
  }
  // The same, `above` = N.AP given (the caller computed it to sort the facet).
  bool crosses_above(std::uint32_t fi, Real above, const Vec3& p, const Vec3& q, Real eps,
                     Real& u) const {
    const Facet& f = facets_[fi];
    if (!(above > eps)) return false;     // (a) N.AP > eps: above the facet's plane
    const Real toward = dot(f.n, q - p);  // (b) N.PQ < 0: heading for it
    if (!(toward < 0)) return false;
    u = -above / toward;
    if (u > 1) return false;  // Q is still above: no collision in this step
    return projects_inside(fi, p + (q - p) * u);
  }
  // Whether the projection of p on facet f's plane lies inside it (closed edges).
  bool projects_inside(std::uint32_t fi, const Vec3& p) const {
    // Barycentric coordinates of p's projection (n is orthogonal to both edges, so p - a can
    // be used as is); the three same-orientation cross products are the same test.
    const Facet& f = facets_[fi];
    const Vec3 w = p - f.a;
    const Real d20 = dot(w, f.e1), d21 = dot(w, f.e2);
    const Real s = (f.d11 * d20 - f.d01 * d21) * f.inv_det;
    const Real t = (f.d00 * d21 - f.d01 * d20) * f.inv_det;
    return s >= -kInsideTolerance && t >= -kInsideTolerance && s + t <= 1 + kInsideTolerance;
  }
  // The closest point of facet f to p, and the sign of p against the surface there.
  Closest closest(std::uint32_t f, const Vec3& p) const;
  // The closest point of the whole mesh to p, a point in the grid's box (see inside_box),
  // cells searched in growing shells until no unvisited cell can hold a closer facet.
  Closest nearest(const Vec3& p) const;
  bool inside_box(const Vec3& p) const {
    return p.x >= lo_.x && p.y >= lo_.y && p.z >= lo_.z && p.x <= hi_.x && p.y <= hi_.y &&
           p.z <= hi_.z;
  }

  // The build's work, bounded by two budgets (facet_grid.cpp): cells in the grid, and the
  // (cell, facet) tests of the build. Tests check the bounds instead of timing the build.
  std::uint64_t cell_count() const { return starts_.empty() ? 0 : starts_.size() - 1; }
  double build_visits() const { return planned_visits(); }
  std::size_t entry_count() const { return entries_.size(); }
  static double cell_budget(std::size_t facets) {
    return std::min(256.0 * double(facets) + 4096, double(1u << 24));
  }
  static double visit_budget(std::size_t facets) {
    return 64.0 * double(facets) + double(1u << 22);
  }

 private:
  std::uint64_t cell_index(int i, int j, int k) const {
    return (std::uint64_t(k) * dims_[1] + std::uint64_t(j)) * dims_[0] + std::uint64_t(i);
  }
  std::array<int, 3> cell_of(const Vec3& x) const {
    return {axis_cell(x, 0), axis_cell(x, 1), axis_cell(x, 2)};
  }
  int axis_cell(const Vec3& x, int d) const {
    // Clamped in floating point first: the conversion of a far (or huge) value is then defined.
    return static_cast<int>(std::clamp<Real>((x[d] - lo_[d]) * inv_cell_, 0, top_[d]));
  }
  std::span<const std::uint32_t> row_facets(const Row& row) const {
    if (row.end - row.begin <= row.ids.size()) return {row.ids.data(), row.end - row.begin};
    return {entries_.data() + row.begin, entries_.data() + row.end};
  }
  // The row's inner box for cell c: the cell less the rounding margin, within the grid's box,
  // kept only if cell_of puts both its corners in c. cell_of is monotone on each axis, so it
  // then puts every point between them in c too: a query box inside (lo <= hi) has both
  // corners in c and meets the grid's box, as the full test requires. Else the box is empty.
  void inner_box(const std::array<int, 3>& c, Row& row) const;
  double planned_visits() const;  // the build's cell tests at cell_ and dims_ (facet_grid.cpp)
  // A query over several cells: their facets gathered into scratch (or every facet, beyond
  // kMaxQueryCells cells).
  std::span<const std::uint32_t> candidates_in_cells(const std::array<int, 3>& c0,
                                                     const std::array<int, 3>& c1,
                                                     std::vector<std::uint32_t>& scratch) const;

  std::vector<Facet> facets_;
  std::vector<PseudoNormals> pseudo_;
  bool closed_ = false;
  Vec3 lo_, hi_;  // the grid's box (facets' boxes grown by the margin)
  Real cell_ = 1, inv_cell_ = 1;
  Real margin_ = 0;  // rounding: facets' boxes and the cells of the plane test are grown by it
  std::array<int, 3> dims_{1, 1, 1};
  Vec3 top_{};  // the last cell's index per axis, as reals (cell_of clamps to it)
  std::vector<std::uint32_t> starts_;  // per cell, into entries_ (CSR)
  std::vector<std::uint32_t> entries_;
};

}  // namespace maille::facets
