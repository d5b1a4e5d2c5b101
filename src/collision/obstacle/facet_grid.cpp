// Facets, their grid and the geometric tests of the inverse-dynamics stage (facet_grid.hpp).
#include "facet_grid.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <utility>

namespace maille::facets {

namespace {

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
std::vector<PseudoNormals> pseudo_normals(const TriMesh& mesh, const std::vector<Facet>& facets) {
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
  std::vector<PseudoNormals> out(mesh.triangles.size());
  for (std::size_t f = 0; f < mesh.triangles.size(); ++f) {
    const auto& t = mesh.triangles[f];
    for (int k = 0; k < 3; ++k) {
      const std::uint32_t i = t[k], j = t[(k + 1) % 3];
      out[f].vertex[k] = unit_or_zero(at_vertex[i]);
      out[f].edge[k] = unit_or_zero(at_edge[{std::min(i, j), std::max(i, j)}]);
    }
  }
  return out;
}

// Whether the triangle (a, b, c), with unit normal n, meets the cube [-half, half]^3: the
// separating-axis test (Akenine-Moeller 2001) on the axes the caller's box overlap does not
// test, the triangle's normal and the nine products of its edges with the cube's axes. The
// caller grows `half` by a margin far above the projections' rounding, so a triangle that
// meets the cell itself (its boundary included) is always kept; rounding can only decide for
// one that meets the grown cube but not the cell.
bool triangle_meets_cube(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& n, Real half) {
  auto separated = [&](const Vec3& axis) {
    const Real pa = dot(axis, a), pb = dot(axis, b), pc = dot(axis, c);
    const Real r = half * (std::abs(axis.x) + std::abs(axis.y) + std::abs(axis.z));
    return std::min({pa, pb, pc}) > r || std::max({pa, pb, pc}) < -r;
  };
  if (separated(n)) return false;
  for (const Vec3& e : {b - a, c - b, a - c}) {
    if (separated({0, -e.z, e.y}) || separated({e.z, 0, -e.x}) || separated({-e.y, e.x, 0}))
      return false;
  }
  return true;
}

// Interleaves the low 10 bits of x, y, z (a Morton code).
std::uint32_t morton(std::uint32_t x, std::uint32_t y, std::uint32_t z) {
  auto spread = [](std::uint32_t v) {
    v &= 0x3ff;
    v = (v | (v << 16)) & 0x030000ff;
    v = (v | (v << 8)) & 0x0300f00f;
    v = (v | (v << 4)) & 0x030c30c3;
    v = (v | (v << 2)) & 0x09249249;
    return v;
  };
  return spread(x) | (spread(y) << 1) | (spread(z) << 2);
}

// The mesh with its triangles in Morton order of their centroids: facets near in space are near
// in memory, so the few a particle tests share cache lines with its neighbours' (the stage is
// bound by memory latency, not arithmetic).
TriMesh spatially_sorted(const TriMesh& mesh) {
  TriMesh out = mesh;
  if (mesh.triangles.empty()) return out;
  Vec3 lo = mesh.vertices.front(), hi = lo;
  for (const Vec3& v : mesh.vertices) lo = component_min(lo, v), hi = component_max(hi, v);
  const Vec3 size = hi - lo;
  std::vector<std::pair<std::uint32_t, std::uint32_t>> keys;  // (code, triangle)
  keys.reserve(mesh.triangles.size());
  for (std::uint32_t t = 0; t < mesh.triangles.size(); ++t) {
    const auto& tri = mesh.triangles[t];
    const Vec3 c = (mesh.vertices[tri[0]] + mesh.vertices[tri[1]] + mesh.vertices[tri[2]]) / 3;
    std::array<std::uint32_t, 3> q{};
    for (int d = 0; d < 3; ++d)
      q[d] = size[d] > 0 ? static_cast<std::uint32_t>(
                               std::clamp<Real>((c[d] - lo[d]) / size[d] * 1023, 0, 1023))
                         : 0;
    keys.push_back({morton(q[0], q[1], q[2]), t});
  }
  std::sort(keys.begin(), keys.end());
  for (std::size_t i = 0; i < keys.size(); ++i) out.triangles[i] = mesh.triangles[keys[i].second];
  return out;
}

}  // namespace

FacetGrid::FacetGrid(const TriMesh& unsorted) : closed_(unsorted.closed()) {
  const TriMesh mesh = spatially_sorted(unsorted);
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
  pseudo_ = pseudo_normals(mesh, facets_);
  if (facets_.empty()) return;
  // Facet boxes are grown by a rounding margin.
  const Vec3 size = hi_ - lo_;
  const Real diagonal = norm(size);
  margin_ = diagonal * Real(1e-9) + std::numeric_limits<Real>::min();
  lo_ -= Vec3{1, 1, 1} * margin_, hi_ += Vec3{1, 1, 1} * margin_;
  // Cells a third of a facet: a particle's query (one cell, most steps) meets about three
  // facets rather than ten; a surface fills few cells of its box, hence the generous budget.
  cell_ = std::max(extent_sum / Real(3 * facets_.size()), diagonal * Real(1e-3));
  // Two budgets: the cells, and the (cell, facet) visits of the build below, so that a few
  // large facets among many small ones (which set a fine cell) cannot make the build test
  // billions of cells (a 24 MB OBJ of 200,000 small and 1,000 large triangles took 284 s).
  const double budget = cell_budget(facets_.size());
  const double visits = visit_budget(facets_.size());
  for (;;) {
    for (int d = 0; d < 3; ++d)
      dims_[d] = std::max(1, static_cast<int>(std::ceil((hi_[d] - lo_[d]) / cell_)));
    if (double(dims_[0]) * dims_[1] * dims_[2] <= budget && planned_visits() <= visits) break;
    cell_ *= Real(1.26);  // about 2x fewer cells per round
  }
  inv_cell_ = 1 / cell_;
  top_ = {Real(dims_[0] - 1), Real(dims_[1] - 1), Real(dims_[2] - 1)};
  // Counting sort of (cell, facet) entries into CSR rows.
  const std::uint64_t cells = std::uint64_t(dims_[0]) * dims_[1] * dims_[2];
  starts_.assign(cells + 1, 0);
  auto each_cell = [&](std::size_t fi, auto&& visit) {
    const Facet& f = facets_[fi];
    const Vec3 b = f.a + f.e1, c = f.a + f.e2;
    const auto c0 = cell_of(component_min(component_min(f.a, b), c));
    const auto c1 = cell_of(component_max(component_max(f.a, b), c));
    // Of the cells its box overlaps, those the triangle meets (cells grown by the rounding
    // margin): a query in one cell then meets about two facets on a tessellated sphere, not
    // the six whose boxes and planes reach it, and a facet through a cell is never left out.
    const Real half = cell_ / 2 + margin_;
    auto test = [&](int i, int j, int k) {
      const Vec3 centre =
          lo_ + Vec3{Real(i) + Real(0.5), Real(j) + Real(0.5), Real(k) + Real(0.5)} * cell_;
      if (triangle_meets_cube(f.a - centre, b - centre, c - centre, f.n, half))
        visit(cell_index(i, j, k));
    };
    // Only the cells near the facet's plane, column by column along the normal's largest
    // axis m: over a column (a cell's square on the other two axes, grown by the margin) the
    // plane's m coordinate spans [lowest, highest] of its four corners, and only the cells of
    // that span (grown by the margin) can meet the triangle: about dims^2 cells for a facet
    // across the grid, not dims^3.
    const int m = std::abs(f.n.x) >= std::abs(f.n.y) && std::abs(f.n.x) >= std::abs(f.n.z) ? 0
                  : std::abs(f.n.y) >= std::abs(f.n.z)                                     ? 1
                                                                                           : 2;
    const int u = (m + 1) % 3, w = (m + 2) % 3;
    if (f.n[m] == 0) {  // degenerate (no normal): every cell of its box
      for (int k = c0[2]; k <= c1[2]; ++k)
        for (int j = c0[1]; j <= c1[1]; ++j)
          for (int i = c0[0]; i <= c1[0]; ++i) test(i, j, k);
      return;
    }
    const Real level = dot(f.n, f.a);  // the plane: n . x = level
    for (int iu = c0[u]; iu <= c1[u]; ++iu)
      for (int iw = c0[w]; iw <= c1[w]; ++iw) {
        Real low = std::numeric_limits<Real>::max(), high = -low;
        for (int corner = 0; corner < 4; ++corner) {
          const Real xu =
              lo_[u] + Real(iu + (corner & 1)) * cell_ + (corner & 1 ? 1 : -1) * margin_;
          const Real xw =
              lo_[w] + Real(iw + (corner >> 1)) * cell_ + (corner >> 1 ? 1 : -1) * margin_;
          const Real xm = (level - f.n[u] * xu - f.n[w] * xw) / f.n[m];
          low = std::min(low, xm), high = std::max(high, xm);
        }
        const Real lo_m = low - margin_, hi_m = high + margin_;
        const Vec3 at_low{lo_m, lo_m, lo_m}, at_high{hi_m, hi_m, hi_m};
        const int k0 = std::max(c0[m], axis_cell(at_low, m));
        const int k1 = std::min(c1[m], axis_cell(at_high, m));
        for (int km = k0; km <= k1; ++km) {
          std::array<int, 3> q{};
          q[m] = km, q[u] = iu, q[w] = iw;
          test(q[0], q[1], q[2]);
        }
      }
  };
  for (std::size_t f = 0; f < facets_.size(); ++f)
    each_cell(f, [&](std::uint64_t cell) { ++starts_[cell + 1]; });
  for (std::uint64_t c = 0; c < cells; ++c) starts_[c + 1] += starts_[c];
  entries_.resize(starts_[cells]);
  std::vector<std::uint32_t> fill(starts_.begin(), starts_.end() - 1);
  for (std::size_t f = 0; f < facets_.size(); ++f)
    each_cell(f, [&](std::uint64_t cell) { entries_[fill[cell]++] = std::uint32_t(f); });
}

// The build's (cell, facet) tests at the current cell size, as each_cell makes them: per facet,
// the columns of its box across its normal's largest axis, at most 4 cells each (the plane
// crosses at most 1 + |n_u| / |n_m| + |n_w| / |n_m| <= 3 cells of a column, and the margin one).
double FacetGrid::planned_visits() const {
  double visits = 0;
  for (const Facet& f : facets_) {
    const Vec3 b = f.a + f.e1, c = f.a + f.e2;
    const Vec3 extent =
        component_max(component_max(f.a, b), c) - component_min(component_min(f.a, b), c);
    const int m = std::abs(f.n.x) >= std::abs(f.n.y) && std::abs(f.n.x) >= std::abs(f.n.z) ? 0
                  : std::abs(f.n.y) >= std::abs(f.n.z)                                     ? 1
                                                                                           : 2;
    double cells[3];
    for (int d = 0; d < 3; ++d)
      cells[d] = std::min(double(dims_[d]), std::floor(extent[d] / cell_) + 2);
    visits += cells[(m + 1) % 3] * cells[(m + 2) % 3] *
              (f.n[m] == 0 ? cells[m] : std::min(cells[m], 4.0));
  }
  return visits;
}

void FacetGrid::inner_box(const std::array<int, 3>& c, Row& row) const {
  std::array<Real, 3> l{}, h{};
  for (int d = 0; d < 3; ++d) {
    const Real start = lo_[d] + Real(c[d]) * cell_;
    l[d] = std::max(start + margin_, lo_[d]);
    h[d] = std::min(start + cell_ - margin_, hi_[d]);
  }
  const Vec3 lo{l[0], l[1], l[2]}, hi{h[0], h[1], h[2]};
  bool found = true;
  for (int d = 0; d < 3; ++d)
    found = found && lo[d] <= hi[d] && axis_cell(lo, d) == c[d] && axis_cell(hi, d) == c[d];
  const Real inf = std::numeric_limits<Real>::infinity();
  row.inner_lo = found ? lo : Vec3{inf, inf, inf};
  row.inner_hi = found ? hi : Vec3{-inf, -inf, -inf};
}

std::span<const std::uint32_t> FacetGrid::candidates_in_cells(
    const std::array<int, 3>& c0, const std::array<int, 3>& c1,
    std::vector<std::uint32_t>& scratch) const {
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

// Ericson, Real-Time Collision Detection, 5.1.5, keeping which feature is closest.
Closest FacetGrid::closest(std::uint32_t fi, const Vec3& p) const {
  const Facet& f = facets_[fi];
  const PseudoNormals& ps = pseudo_[fi];
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
    r.point = a, pseudo = ps.vertex[0];
  } else if (d3 >= 0 && d4 <= d3) {
    r.point = b, pseudo = ps.vertex[1];
  } else if (vc <= 0 && d1 >= 0 && d3 <= 0) {
    r.point = a + f.e1 * (d1 / (d1 - d3)), pseudo = ps.edge[0];
  } else if (d6 >= 0 && d5 <= d6) {
    r.point = c, pseudo = ps.vertex[2];
  } else if (vb <= 0 && d2 >= 0 && d6 <= 0) {
    r.point = a + f.e2 * (d2 / (d2 - d6)), pseudo = ps.edge[2];
  } else if (va <= 0 && (d4 - d3) >= 0 && (d5 - d6) >= 0) {
    r.point = b + (c - b) * ((d4 - d3) / ((d4 - d3) + (d5 - d6))), pseudo = ps.edge[1];
  } else {
    const Real denom = 1 / (va + vb + vc);
    r.point = a + f.e1 * (vb * denom) + f.e2 * (vc * denom), pseudo = f.n;
  }
  const Vec3 d = p - r.point;
  r.distance2 = dot(d, d);
  r.sign = dot(d, pseudo) < 0 ? Real(-1) : Real(1);
  return r;
}

Closest FacetGrid::nearest(const Vec3& p) const {
  Closest best;
  best.distance2 = std::numeric_limits<Real>::max();
  if (facets_.empty()) return best;
  const auto c = cell_of(p);  // p is in the grid's box (callers check): c holds it
  const int most = std::max({dims_[0], dims_[1], dims_[2]});
  for (int r = 0; r <= most; ++r) {
    // Every cell at Chebyshev distance r from c (the shell), clamped to the grid.
    for (int k = std::max(0, c[2] - r); k <= std::min(dims_[2] - 1, c[2] + r); ++k)
      for (int j = std::max(0, c[1] - r); j <= std::min(dims_[1] - 1, c[1] + r); ++j)
        for (int i = std::max(0, c[0] - r); i <= std::min(dims_[0] - 1, c[0] + r); ++i) {
          if (std::max({std::abs(i - c[0]), std::abs(j - c[1]), std::abs(k - c[2])}) != r) continue;
          const std::uint64_t cell = cell_index(i, j, k);
          for (std::uint32_t e = starts_[cell]; e < starts_[cell + 1]; ++e) {
            const Closest cl = closest(entries_[e], p);
            if (cl.distance2 < best.distance2) best = cl;
          }
        }
    // Cells beyond shell r are at least r cells (less p's offset in its cell) away from p.
    const Real reach = Real(r) * cell_;
    if (best.distance2 <= reach * reach) break;
  }
  return best;
}

}  // namespace maille::facets
