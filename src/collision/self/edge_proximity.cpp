#include "edge_proximity.hpp"

#include <algorithm>
#include <bit>
#include <cmath>
#include <limits>
#include <tuple>

#include "../thread_lists.hpp"
#include "broad_phase.hpp"
#include "maille/detail/csr.hpp"
#include "maille/self_collision.hpp"
#include "maille/shared_laws.hpp"

namespace maille::collision {

namespace {

// The closest points of edges a and b at x: the parameters and the gap vector between them.
struct Closest {
  Real s = 0, t = 0;
  Vec3 d{};
};
Closest closest(const std::array<std::uint32_t, 2>& a, const std::array<std::uint32_t, 2>& b,
                const Vec3* x) {
  Closest c;
  law::edge_edge_params(x[a[0]], x[a[1]], x[b[0]], x[b[1]], c.s, c.t);
  c.d = x[a[0]] * (1 - c.s) + x[a[1]] * c.s - (x[b[0]] * (1 - c.t) + x[b[1]] * c.t);
  return c;
}

}  // namespace

EdgeProximity::EdgeProximity(const Model& m, const std::vector<std::uint32_t>& set,
                             const std::vector<std::array<std::uint32_t, 3>>& faces,
                             int topological_radius, std::size_t max_contacts)
    : local_(m.points.size(), -1), max_contacts_(max_contacts), radius_links_(topological_radius) {
  for (std::size_t k = 0; k < set.size(); ++k) local_[set[k]] = std::int32_t(k);
  for (const auto& t : faces)
    for (int e = 0; e < 3; ++e) {
      const std::uint32_t a = t[std::size_t(e)], b = t[std::size_t((e + 1) % 3)];
      edges_.push_back({std::min(a, b), std::max(a, b)});
    }
  std::sort(edges_.begin(), edges_.end());
  edges_.erase(std::unique(edges_.begin(), edges_.end()), edges_.end());
  for (const auto& e : edges_) corners_.insert(corners_.end(), e.begin(), e.end());
  std::sort(corners_.begin(), corners_.end());
  corners_.erase(std::unique(corners_.begin(), corners_.end()), corners_.end());
}

std::size_t EdgeProximity::cell_of(const Vec3& p) const {
  const Vec3 q = (p - lo_) / cell_;
  auto clampi = [](Real v, std::int64_t n) {
    return std::clamp<std::int64_t>(std::int64_t(std::floor(v)), 0, n - 1);
  };
  return std::size_t((clampi(q.z, nz_) * ny_ + clampi(q.y, ny_)) * nx_ + clampi(q.x, nx_));
}

// Cells of about the longest edge (at least the reach); each edge goes into the cells its box
// grown by `grow` overlaps (counting sort, two passes), as TriangleProximity::bin does.
void EdgeProximity::bin(const Vec3* x, Real grow, const std::vector<std::uint32_t>* only) {
  Vec3 lo = x[corners_.front()], hi = lo;
  for (const std::uint32_t c : corners_) {
    lo = {std::min(lo.x, x[c].x), std::min(lo.y, x[c].y), std::min(lo.z, x[c].z)};
    hi = {std::max(hi.x, x[c].x), std::max(hi.y, x[c].y), std::max(hi.z, x[c].z)};
  }
  Real cell = grow;
  for (const auto& e : edges_) cell = std::max(cell, norm(x[e[1]] - x[e[0]]));
  const Vec3 ext = hi - lo;
  while ((ext.x / cell + 1) * (ext.y / cell + 1) * (ext.z / cell + 1) >
         Real(8 * edges_.size() + 4096))
    cell = std::max(cell * Real(1.25), std::numeric_limits<Real>::min());
  lo_ = lo;
  cell_ = cell;
  nx_ = std::int64_t(ext.x / cell) + 1;
  ny_ = std::int64_t(ext.y / cell) + 1;
  nz_ = std::int64_t(ext.z / cell) + 1;
  const auto cells = std::size_t(nx_ * ny_ * nz_);
  const Vec3 g{grow, grow, grow};
  auto each_cell = [&](std::size_t e, auto&& fn) {
    const Vec3 &p = x[edges_[e][0]], &q = x[edges_[e][1]];
    const Vec3 a = Vec3{std::min(p.x, q.x), std::min(p.y, q.y), std::min(p.z, q.z)} - g;
    const Vec3 b = Vec3{std::max(p.x, q.x), std::max(p.y, q.y), std::max(p.z, q.z)} + g;
    const std::size_t c0 = cell_of(a), c1 = cell_of(b);
    const auto i0 = std::int64_t(c0) % nx_, j0 = std::int64_t(c0) / nx_ % ny_,
               k0 = std::int64_t(c0) / (nx_ * ny_);
    const auto i1 = std::int64_t(c1) % nx_, j1 = std::int64_t(c1) / nx_ % ny_,
               k1 = std::int64_t(c1) / (nx_ * ny_);
    each_cell_in(i0, i1, j0, j1, k0, k1, nx_, ny_, fn);
  };
  bin_primitives(cells, edges_.size(), only, cell_start_, cell_edges_, each_cell);
}

// Whether a corner of the pair is a colliding particle (two fixed edges never meet).
bool EdgeProximity::moves(const std::array<std::uint32_t, 2>& a,
                          const std::array<std::uint32_t, 2>& b) const {
  return local_[a[0]] >= 0 || local_[a[1]] >= 0 || local_[b[0]] >= 0 || local_[b[1]] >= 0;
}

bool EdgeProximity::excluded(std::uint32_t a, std::uint32_t b,
                             const TopologicalExclusion* exclusion) const {
  const auto &ea = edges_[a], &eb = edges_[b];
  for (const std::uint32_t p : ea)
    for (const std::uint32_t q : eb)
      if (p == q) return true;  // a shared corner: the faces' own fold, never a contact
  // The exclusion's rows know the particles only: a fixed corner (a held border) is taken one
  // link deep by the faces' own edges, so that a border's edges do not touch the free edges
  // next to them at rest.
  if (radius_links_ >= 1)
    for (const std::uint32_t p : ea)
      for (const std::uint32_t q : eb)
        if ((local_[p] < 0 || local_[q] < 0) && linked(p, q)) return true;
  if (!exclusion) return false;
  for (const std::uint32_t p : ea)
    for (const std::uint32_t q : eb)
      if (local_[p] >= 0 && local_[q] >= 0 &&
          exclusion->excluded(std::uint32_t(local_[p]), std::uint32_t(local_[q])))
        return true;
  return false;
}

bool EdgeProximity::linked(std::uint32_t p, std::uint32_t q) const {
  const std::array<std::uint32_t, 2> e{std::min(p, q), std::max(p, q)};
  return std::binary_search(edges_.begin(), edges_.end(), e);
}

bool EdgeProximity::find_pairs(const Vec3* x, Real reach, const TopologicalExclusion* exclusion,
                               int threads, std::vector<std::array<std::uint32_t, 2>>& out,
                               const Real* grow, const std::vector<std::uint32_t>* only,
                               const PairReach* pair_reach) {
  Real longest = 0;
  for (const auto& e : edges_) longest = std::max(longest, norm(x[e[1]] - x[e[0]]));
  // A pair within `reach` has a's midpoint within reach + |a| / 2 of b: in b's grown cells.
  // (Cells per edge share, as TriangleProximity::candidates has, were tried: on
  // cloth_on_sphere_vbd the shares are near the largest and the overlaps' cells cost more.)
  bin(x, reach + longest / 2, only);
  const std::size_t cap = start_lists(per_thread_pairs_, thread_full_, threads, max_contacts_);
  const auto n = static_cast<std::int64_t>(edges_.size());
  // Each edge's box: a pair whose boxes are farther apart than the reach along an axis is
  // farther than the reach (six compares before the closest points' divisions; most of a cell's
  // edges fail them).
  boxes_.resize(edges_.size());
  for (std::size_t e = 0; e < edges_.size(); ++e) {
    const Vec3 &p = x[edges_[e][0]], &q = x[edges_[e][1]];
    boxes_[e] = {{std::min(p.x, q.x), std::min(p.y, q.y), std::min(p.z, q.z)},
                 {std::max(p.x, q.x), std::max(p.y, q.y), std::max(p.z, q.z)}};
  }
#pragma omp parallel for schedule(dynamic, 256) num_threads(threads) if (threads > 1)
  for (std::int64_t i = 0; i < n; ++i) {
    auto& list = per_thread_pairs_[std::size_t(thread_id())];
    const auto a = std::uint32_t(i);
    const auto& ea = edges_[a];
    const Box& ba = boxes_[a];
    // Pair (a, b) past the boxes' test: the closest points within the reach.
    auto consider = [&](std::uint32_t b, Real r) {
      if (!moves(ea, edges_[b]) || excluded(a, b, exclusion)) return true;
      const Closest cl = closest(ea, edges_[b], x);
      if (!(dot(cl.d, cl.d) < r * r)) return true;
      if (list.size() >= cap) {
        thread_full_[std::size_t(thread_id())] = 1;
        return false;
      }
      list.push_back({std::min(a, b), std::max(a, b)});
      return true;
    };
    const std::size_t c = cell_of((x[ea[0]] + x[ea[1]]) * Real(0.5));
    for (std::uint32_t k = cell_start_[c]; k < cell_start_[c + 1]; ++k) {
      const std::uint32_t b = cell_edges_[k];
      if (only ? b == a : b <= a) continue;  // with `only`: either order, once below
      const Box& bb = boxes_[b];
      const Real g = grow ? grow[a] + grow[b] : reach;
      if (ba.lo.x > bb.hi.x + g || bb.lo.x > ba.hi.x + g || ba.lo.y > bb.hi.y + g ||
          bb.lo.y > ba.hi.y + g || ba.lo.z > bb.hi.z + g || bb.lo.z > ba.hi.z + g)
        continue;
      // The pair's own reach (pair_reach): the boxes again before the closest points.
      const Real r = pair_reach ? std::min(reach, pair_reach->of(ea, edges_[b])) : reach;
      if (pair_reach && (ba.lo.x > bb.hi.x + r || bb.lo.x > ba.hi.x + r || ba.lo.y > bb.hi.y + r ||
                         bb.lo.y > ba.hi.y + r || ba.lo.z > bb.hi.z + r || bb.lo.z > ba.hi.z + r))
        continue;
      if (!consider(b, r)) break;
    }
  }
  for (const std::uint8_t t : thread_full_) full_ = full_ || t != 0;
  if (full_) return false;
  room_for_any_split(per_thread_pairs_, cap);
  out.clear();
  std::size_t total = 0;
  for (const auto& list : per_thread_pairs_) total += list.size();
  detail::reserve_pow2(out, total);
  for (const auto& list : per_thread_pairs_) out.insert(out.end(), list.begin(), list.end());
  if (!std::is_sorted(out.begin(), out.end())) std::sort(out.begin(), out.end());  // threads
  if (only) out.erase(std::unique(out.begin(), out.end()), out.end());
  return true;
}

Real EdgeProximity::PairReach::of(const std::array<std::uint32_t, 2>& a,
                                  const std::array<std::uint32_t, 2>& b) const {
  Real closing2 = 0;
  for (const std::uint32_t p : a)
    for (const std::uint32_t q : b) closing2 = std::max(closing2, norm2(v[p] - v[q]));
  return radius + pair_margin(radius, h, closing2, max_margin);
}

bool EdgeProximity::pairs_hold(const Vec3* x, Real radius, Real reach,
                               const TopologicalExclusion* exclusion) const {
  if (pairs_reach_ != reach || pairs_exclusion_ != exclusion) return false;
  // Each closest point moves no farther than its edge's corners: the gap by at most twice that.
  return 2 * largest_move(x, corners_, anchor_) <= reach - radius;
}

bool EdgeProximity::bound_motion(const Vec3* x, Real share, Real radius, Real* bound) const {
  if (edges_.size() < 2) return true;
  if (pairs_reach_ < 0) return false;
  for (const auto& [a, b] : pairs_) {
    const auto &ea = edges_[a], &eb = edges_[b];
    const Real d = law::stencil_bound(share, norm(closest(ea, eb, x).d), radius, kStencilFloor);
    for (const std::uint32_t c : {ea[0], ea[1], eb[0], eb[1]}) bound[c] = std::min(bound[c], d);
  }
  return true;
}

std::uint64_t EdgeProximity::apply(const Vec3* x, const Vec3* v, Vec3* f, const TriangleResponse& r,
                                   const TopologicalExclusion* exclusion, int threads) {
  full_ = false;
  all_.clear();
  if (edges_.size() < 2) return 0;
  const Real reach = r.radius * (1 + TriangleProximity::kSkinFraction);
  if (!pairs_hold(x, r.radius, reach, exclusion)) {
    pairs_reach_ = -1;
    if (!find_pairs(x, reach, exclusion, threads, pairs_)) return 0;
    take_anchor(x, corners_, anchor_);
    pairs_reach_ = reach;
    pairs_exclusion_ = exclusion;
  }
  per_thread_.resize(std::size_t(std::max(threads, 1)));
  for (auto& list : per_thread_) list.clear();
  const auto n = static_cast<std::int64_t>(pairs_.size());
  // At most one contact per listed pair: the lists hold at most the pairs (within the budget).
#pragma omp parallel for schedule(static) num_threads(threads) if (threads > 1)
  for (std::int64_t i = 0; i < n; ++i) {
    const std::uint32_t a = pairs_[std::size_t(i)][0], b = pairs_[std::size_t(i)][1];
    const auto &ea = edges_[a], &eb = edges_[b];
    const Closest cl = closest(ea, eb, x);
    if (!law::edge_edge_acts(cl.s, cl.t, true, true, true, true))  // kPointCorners
      continue;
    const Real d2 = dot(cl.d, cl.d);
    if (!(d2 < r.radius * r.radius) || d2 == 0) continue;
    const Vec3 dv =
        v[ea[0]] * (1 - cl.s) + v[ea[1]] * cl.s - (v[eb[0]] * (1 - cl.t) + v[eb[1]] * cl.t);
    Vec3 force = law::stencil_contact_force(cl.d, dv, r.stiffness, r.damping, r.radius);
    if (r.friction > 0) {  // Coulomb-like, as the point-triangle contacts
      const Vec3 nrm = cl.d / std::sqrt(d2);
      const Vec3 vt = dv - nrm * dot(dv, nrm);
      force -=
          vt * (r.friction * std::abs(dot(force, nrm)) / std::max(norm(vt), kSelfCollisionSlip));
    }
    per_thread_[std::size_t(thread_id())].push_back(
        {a, b, force, cl.s, cl.t, r.radius - std::sqrt(d2)});
  }
  room_for_any_split(per_thread_, max_contacts_ / per_thread_.size());
  std::size_t total = 0;
  for (const auto& list : per_thread_) total += list.size();
  detail::reserve_pow2(all_, total);
  for (const auto& list : per_thread_) all_.insert(all_.end(), list.begin(), list.end());
  // (edge, edge) order: the same sums whatever the threads.
  std::sort(all_.begin(), all_.end(), [](const Contact& p, const Contact& q) {
    return std::tie(p.a, p.b) < std::tie(q.a, q.b);
  });
  for (const Contact& c : all_) {
    const auto &ea = edges_[c.a], &eb = edges_[c.b];
    f[ea[0]] += c.force * (1 - c.s);
    f[ea[1]] += c.force * c.s;
    f[eb[0]] -= c.force * (1 - c.t);
    f[eb[1]] -= c.force * c.t;
  }
  return all_.size();
}

void EdgeProximity::candidates(const Vec3* x, const Vec3* v, Real radius, Real h, Real max_margin,
                               const TopologicalExclusion* exclusion, int threads,
                               std::vector<std::array<std::uint32_t, 4>>& out,
                               std::vector<std::uint8_t>& particles) {
  full_ = false;
  if (edges_.size() < 2) return;
  // Each edge's share of a pair's reach: half the radius and of the smallest margin, and its
  // corners' largest speed relative to the colliding corners' mean velocity times kMotionFactor
  // h (two corners close at most at the sum of their speeds relative to any common velocity,
  // so a pair's margin is at most the sum of its edges' shares: the boxes grown by them are a
  // necessary test, and the candidates are those of a search at the full reach).
  Vec3 mean{};
  for (const std::uint32_t c : corners_) mean += v[c];
  mean = mean * (Real(1) / Real(corners_.size()));
  grow_.resize(edges_.size());
  Real widest = 0;
  for (std::size_t e = 0; e < edges_.size(); ++e) {
    const Real speed =
        std::sqrt(std::max(norm2(v[edges_[e][0]] - mean), norm2(v[edges_[e][1]] - mean)));
    grow_[e] = Real(0.5) * (radius + kMinMarginFraction * radius) + kMotionFactor * h * speed;
    widest = std::max(widest, grow_[e]);
  }
  // No pair reaches farther than its two shares: the grid's cells are sized for this step's
  // motion, not for the wide margin (kept for rebuilds, up to eight times a resting cloth's);
  // the same pairs (a thousandth more for the rounding) with fewer edges per cell.
  // Each pair within its own reach: the radius and its margin, from the largest speed of a
  // corner of one edge relative to a corner of the other (PairReach).
  const Real reach = std::min(radius + max_margin, Real(1.001) * 2 * widest);
  const PairReach pair_reach{v, radius, h, max_margin};
  if (!find_pairs(x, reach, exclusion, threads, wide_pairs_, grow_.data(), nullptr, &pair_reach))
    return;
  for (const auto& pair : wide_pairs_) {
    const auto &ea = edges_[pair[0]], &eb = edges_[pair[1]];
    out.push_back({ea[0], ea[1], eb[0], eb[1]});
    particles.push_back(kPointCorners);
  }
}

void EdgeProximity::candidates_near(const Vec3* x, const std::uint8_t* moved, Real reach,
                                    const TopologicalExclusion* exclusion, int threads,
                                    std::vector<std::array<std::uint32_t, 4>>& out,
                                    std::vector<std::uint8_t>& particles) {
  full_ = false;
  if (edges_.size() < 2) return;
  from_.clear();
  for (std::size_t e = 0; e < edges_.size(); ++e)
    if (moved[edges_[e][0]] || moved[edges_[e][1]]) from_.push_back(std::uint32_t(e));
  if (from_.empty() || !find_pairs(x, reach, exclusion, threads, wide_pairs_, nullptr, &from_))
    return;
  for (const auto& pair : wide_pairs_) {
    const auto &ea = edges_[pair[0]], &eb = edges_[pair[1]];
    out.push_back({ea[0], ea[1], eb[0], eb[1]});
    particles.push_back(kPointCorners);
  }
}

double EdgeProximity::energy(Real stiffness) const {
  double e = 0;
  for (const Contact& c : all_) e += 0.5 * double(stiffness) * double(c.gap) * double(c.gap);
  return e;
}

}  // namespace maille::collision
