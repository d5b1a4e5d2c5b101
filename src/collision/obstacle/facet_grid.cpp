// Facets, their grid and the geometric tests of the inverse-dynamics stage (facet_grid.hpp).
#include "facet_grid.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <utility>

namespace maille::facets {

namespace {

// Barycentric tolerance: a point this close (relative to the facet) to a shared edge counts as
// inside both facets, so a crossing exactly on a joint is never lost to rounding (the hit then
// goes to the earliest, or the first, of them: either one stops the particle).
constexpr Real kInsideTolerance = Real(1e-9);
// Beyond this many cells a query tests every facet (a particle crossing the whole obstacle in
// one step): slower, never wrong.
constexpr std::uint64_t kMaxQueryCells = 4096;

Vec3 unit_or_zero(const Vec3& v) {
  const Real l = norm(v);
  return l > 0 ? v / l : Vec3{};
}

Real angle_between(const Vec3& a, const Vec3& b) {
  return std::atan2(norm(cross(a, b)), dot(a, b));
}

Vec3 component_min(const Vec3& a, const Vec3& b) {
  return {std::min(a.x, b.x), std::min(a.y, b.y), std::min(a.z, b.z)};
}
Vec3 component_max(const Vec3& a, const Vec3& b) {
  return {std::max(a.x, b.x), std::max(a.y, b.y), std::max(a.z, b.z)};
}

// Pseudo-normals (Baerentzen and Aanaes): at an edge the sum of its faces' normals, at a vertex
// the sum of the normals weighted by the faces' angles there. Their sign test is exact for
// closest points on edges and vertices, where a face normal alone misjudges inside/outside.
void set_pseudo_normals(const TriMesh& mesh, std::vector<Facet>& facets) {
  std::vector<Vec3> at_vertex(mesh.vertices.size());
  std::map<std::pair<std::uint32_t, std::uint32_t>, Vec3> at_edge;
  for (std::size_t f = 0; f < mesh.triangles.size(); ++f) {
    const auto& t = mesh.triangles[f];
    for (int k = 0; k < 3; ++k) {
      const std::uint32_t i = t[k], j = t[(k + 1) % 3], l = t[(k + 2) % 3];
      const Vec3& x = mesh.vertices[i];
      at_vertex[i] += facets[f].n * angle_between(mesh.vertices[j] - x, mesh.vertices[l] - x);
      at_edge[{std::min(i, j), std::max(i, j)}] += facets[f].n;
    }
  }
  for (std::size_t f = 0; f < mesh.triangles.size(); ++f) {
    const auto& t = mesh.triangles[f];
    for (int k = 0; k < 3; ++k) {
      const std::uint32_t i = t[k], j = t[(k + 1) % 3];
      facets[f].vertex_pseudo[k] = unit_or_zero(at_vertex[i]);
      facets[f].edge_pseudo[k] = unit_or_zero(at_edge[{std::min(i, j), std::max(i, j)}]);
    }
  }
}

}  // namespace

FacetGrid::FacetGrid(const TriMesh& mesh) : closed_(mesh.closed()) {
  facets_.reserve(mesh.triangles.size());
  lo_ = Vec3{1, 1, 1} * std::numeric_limits<Real>::max();
  hi_ = lo_ * Real(-1);
  Real extent_sum = 0;
  for (const auto& t : mesh.triangles) {
    Facet f{};
    const Vec3 &a = mesh.vertices[t[0]], &b = mesh.vertices[t[1]], &c = mesh.vertices[t[2]];
    f.a = a, f.e1 = b - a, f.e2 = c - a;
    f.n = unit_or_zero(cross(f.e1, f.e2));
    f.d00 = dot(f.e1, f.e1), f.d01 = dot(f.e1, f.e2), f.d11 = dot(f.e2, f.e2);
    const Real det = f.d00 * f.d11 - f.d01 * f.d01;
    f.inv_det = det > 0 ? 1 / det : 0;
    facets_.push_back(f);
    const Vec3 flo = component_min(component_min(a, b), c);
    const Vec3 fhi = component_max(component_max(a, b), c);
    lo_ = component_min(lo_, flo), hi_ = component_max(hi_, fhi);
    extent_sum += std::max({fhi.x - flo.x, fhi.y - flo.y, fhi.z - flo.z});
  }
  set_pseudo_normals(mesh, facets_);
  if (facets_.empty()) return;
  // Facet boxes are grown by a rounding margin.
  const Vec3 size = hi_ - lo_;
  const Real diagonal = norm(size);
  margin_ = diagonal * Real(1e-9) + std::numeric_limits<Real>::min();
  lo_ -= Vec3{1, 1, 1} * margin_, hi_ += Vec3{1, 1, 1} * margin_;
  // Cells a third of a facet: a particle's query (one cell, most steps) meets about three
  // facets rather than ten; a surface fills few cells of its box, hence the generous budget.
  cell_ = std::max(extent_sum / Real(3 * facets_.size()), diagonal * Real(1e-3));
  const double budget = std::min(256.0 * double(facets_.size()) + 4096, double(1u << 24));
  for (;;) {
    for (int d = 0; d < 3; ++d)
      dims_[d] = std::max(1, static_cast<int>(std::ceil((hi_[d] - lo_[d]) / cell_)));
    if (double(dims_[0]) * dims_[1] * dims_[2] <= budget) break;
    cell_ *= Real(1.26);  // about 2x fewer cells per round
  }
  inv_cell_ = 1 / cell_;
  margin_ = std::max(margin_, cell_ / 2);
  // Counting sort of (cell, facet) entries into CSR rows.
  const std::uint64_t cells = std::uint64_t(dims_[0]) * dims_[1] * dims_[2];
  starts_.assign(cells + 1, 0);
  auto each_cell = [&](std::size_t fi, auto&& visit) {
    const Facet& f = facets_[fi];
    const Vec3 b = f.a + f.e1, c = f.a + f.e2;
    const auto c0 = cell_of(component_min(component_min(f.a, b), c));
    const auto c1 = cell_of(component_max(component_max(f.a, b), c));
    for (int k = c0[2]; k <= c1[2]; ++k)
      for (int j = c0[1]; j <= c1[1]; ++j)
        for (int i = c0[0]; i <= c1[0]; ++i) visit(cell_index(i, j, k));
  };
  for (std::size_t f = 0; f < facets_.size(); ++f)
    each_cell(f, [&](std::uint64_t cell) { ++starts_[cell + 1]; });
  for (std::uint64_t c = 0; c < cells; ++c) starts_[c + 1] += starts_[c];
  entries_.resize(starts_[cells]);
  std::vector<std::uint32_t> fill(starts_.begin(), starts_.end() - 1);
  for (std::size_t f = 0; f < facets_.size(); ++f)
    each_cell(f, [&](std::uint64_t cell) { entries_[fill[cell]++] = std::uint32_t(f); });
}

std::array<int, 3> FacetGrid::cell_of(const Vec3& x) const {
  std::array<int, 3> c{};
  for (int d = 0; d < 3; ++d) {
    // Clamped in floating point first: the conversion of a far (or huge) value is then defined.
    const Real t = std::clamp<Real>((x[d] - lo_[d]) * inv_cell_, 0, Real(dims_[d] - 1));
    c[d] = static_cast<int>(t);
  }
  return c;
}

std::span<const std::uint32_t> FacetGrid::candidates(const Vec3& lo, const Vec3& hi,
                                                     std::vector<std::uint32_t>& scratch) const {
  if (facets_.empty()) return {};
  for (int d = 0; d < 3; ++d)
    if (!(hi[d] >= lo_[d] && lo[d] <= hi_[d])) return {};  // NaN misses too
  const auto c0 = cell_of(lo), c1 = cell_of(hi);
  if (c0 == c1) {
    const std::uint64_t c = cell_index(c0[0], c0[1], c0[2]);
    return {entries_.data() + starts_[c], entries_.data() + starts_[c + 1]};
  }
  scratch.clear();
  const std::uint64_t n =
      std::uint64_t(c1[0] - c0[0] + 1) * (c1[1] - c0[1] + 1) * std::uint64_t(c1[2] - c0[2] + 1);
  if (n > kMaxQueryCells) {
    for (std::uint32_t f = 0; f < facets_.size(); ++f) scratch.push_back(f);
    return scratch;
  }
  for (int k = c0[2]; k <= c1[2]; ++k)
    for (int j = c0[1]; j <= c1[1]; ++j)
      for (int i = c0[0]; i <= c1[0]; ++i) {
        const std::uint64_t c = cell_index(i, j, k);
        scratch.insert(scratch.end(), entries_.begin() + starts_[c],
                       entries_.begin() + starts_[c + 1]);
      }
  return scratch;
}

bool FacetGrid::crosses(std::uint32_t fi, const Vec3& p, const Vec3& q, Real eps, Real& u) const {
  const Facet& f = facets_[fi];
  const Real above = dot(f.n, p - f.a);  // (a) N.AP > eps: above the facet's plane
  if (!(above > eps)) return false;
  const Real toward = dot(f.n, q - p);  // (b) N.PQ < 0: heading for it
  if (!(toward < 0)) return false;
  u = -above / toward;
  if (u > 1) return false;  // Q is still above: no collision in this step
  return projects_inside(fi, p + (q - p) * u);
}

bool FacetGrid::projects_inside(std::uint32_t fi, const Vec3& p) const {
  // Barycentric coordinates of p's projection (n is orthogonal to both edges, so p - a can be
  // used as is); the brief's three same-orientation cross products are the same test.
  const Facet& f = facets_[fi];
  const Vec3 w = p - f.a;
  const Real d20 = dot(w, f.e1), d21 = dot(w, f.e2);
  const Real s = (f.d11 * d20 - f.d01 * d21) * f.inv_det;
  const Real t = (f.d00 * d21 - f.d01 * d20) * f.inv_det;
  return s >= -kInsideTolerance && t >= -kInsideTolerance && s + t <= 1 + kInsideTolerance;
}

// Ericson, Real-Time Collision Detection, 5.1.5, keeping which feature is closest.
Closest FacetGrid::closest(std::uint32_t fi, const Vec3& p) const {
  const Facet& f = facets_[fi];
  const Vec3 a = f.a, b = f.a + f.e1, c = f.a + f.e2;
  Closest r;
  r.facet = fi;
  Vec3 pseudo;
  const Vec3 ap = p - a;
  const Real d1 = dot(f.e1, ap), d2 = dot(f.e2, ap);
  const Vec3 bp = p - b;
  const Real d3 = dot(f.e1, bp), d4 = dot(f.e2, bp);
  const Vec3 cp = p - c;
  const Real d5 = dot(f.e1, cp), d6 = dot(f.e2, cp);
  const Real va = d3 * d6 - d5 * d4, vb = d5 * d2 - d1 * d6, vc = d1 * d4 - d3 * d2;
  if (d1 <= 0 && d2 <= 0) {
    r.point = a, pseudo = f.vertex_pseudo[0];
  } else if (d3 >= 0 && d4 <= d3) {
    r.point = b, pseudo = f.vertex_pseudo[1];
  } else if (vc <= 0 && d1 >= 0 && d3 <= 0) {
    r.point = a + f.e1 * (d1 / (d1 - d3)), pseudo = f.edge_pseudo[0];
  } else if (d6 >= 0 && d5 <= d6) {
    r.point = c, pseudo = f.vertex_pseudo[2];
  } else if (vb <= 0 && d2 >= 0 && d6 <= 0) {
    r.point = a + f.e2 * (d2 / (d2 - d6)), pseudo = f.edge_pseudo[2];
  } else if (va <= 0 && (d4 - d3) >= 0 && (d5 - d6) >= 0) {
    r.point = b + (c - b) * ((d4 - d3) / ((d4 - d3) + (d5 - d6))), pseudo = f.edge_pseudo[1];
  } else {
    const Real denom = 1 / (va + vb + vc);
    r.point = a + f.e1 * (vb * denom) + f.e2 * (vc * denom), pseudo = f.n;
  }
  const Vec3 d = p - r.point;
  r.distance2 = dot(d, d);
  r.sign = dot(d, pseudo) < 0 ? Real(-1) : Real(1);
  return r;
}

}  // namespace maille::facets
