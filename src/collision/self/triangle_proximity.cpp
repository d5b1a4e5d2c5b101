#include "triangle_proximity.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <tuple>

#include "../thread_lists.hpp"
#include "broad_phase.hpp"
#include "maille/detail/csr.hpp"
#include "maille/self_collision.hpp"
#include "maille/shared_laws.hpp"

namespace maille::collision {

// The shared law's weights (include/maille/detail/contact_laws.glsl), as an array.
std::array<Real, 3> closest_weights(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c) {
  const Vec3 w = law::triangle_closest_weights(p, a, b, c);
  return {w.x, w.y, w.z};
}

Feature feature_of(const std::array<std::uint32_t, 3>& tri, std::uint32_t triangle,
                   const std::array<Real, 3>& w) {
  Feature f;
  law::triangle_feature({w[0], w[1], w[2]}, tri[0], tri[1], tri[2], triangle, f.kind, f.a, f.b);
  return f;
}

TriangleProximity::TriangleProximity(const Model& m, const std::vector<std::uint32_t>& set,
                                     const std::vector<std::uint8_t>& groups_mask,
                                     std::size_t max_contacts)
    : set_(set), free_count_(set.size()), local_(m.points.size(), -1), max_contacts_(max_contacts) {
  for (std::size_t k = 0; k < set.size(); ++k) local_[set[k]] = std::int32_t(k);
  for (const auto& t : m.surface.triangles)
    if (groups_mask[t[0]] && groups_mask[t[1]] && groups_mask[t[2]]) tris_.push_back(t);
  // The fixed and driven points of the groups probe the faces too (a free face must not pass
  // through a held point), after the particles: each with the points it shares a face with,
  // its neighbourhood for a topological radius of one link or more.
  for (std::uint32_t p = 0; p < m.points.size(); ++p)
    if (groups_mask[p] && local_[p] < 0 && !(m.points.inv_mass[p] > 0)) set_.push_back(p);
  std::vector<std::int32_t> probe(m.points.size(), -1);
  for (std::size_t k = free_count_; k < set_.size(); ++k)
    probe[set_[k]] = std::int32_t(k - free_count_);
  std::vector<std::vector<std::uint32_t>> ring(set_.size() - free_count_);
  for (const auto& t : tris_)
    for (const std::uint32_t c : t)
      if (probe[c] >= 0)
        for (const std::uint32_t o : t)
          if (o != c) ring[std::size_t(probe[c])].push_back(o);
  ring_start_.assign(1, 0);
  for (auto& r : ring) {
    std::sort(r.begin(), r.end());
    r.erase(std::unique(r.begin(), r.end()), r.end());
    ring_points_.insert(ring_points_.end(), r.begin(), r.end());
    ring_start_.push_back(std::uint32_t(ring_points_.size()));
  }
  tracked_ = set_;
  for (const auto& t : tris_) tracked_.insert(tracked_.end(), t.begin(), t.end());
  std::sort(tracked_.begin(), tracked_.end());
  tracked_.erase(std::unique(tracked_.begin(), tracked_.end()), tracked_.end());
}

// A grid over the particles' box, cells of about the longest triangle box side; triangles go
// into the cells their boxes grown by `grow` overlap (counting sort, two passes).
void TriangleProximity::bin(const Vec3* x, Real grow_by, const std::vector<std::uint32_t>* only,
                            const Real* grow_each) {
  xs_.resize(set_.size());
  for (std::size_t k = 0; k < set_.size(); ++k) xs_[k] = x[set_[k]];
  const Box box = bounds(xs_.data(), std::uint32_t(xs_.size()));
  Real cell = grow_by;
  for (const auto& t : tris_)
    for (int e = 0; e < 3; ++e)
      cell = std::max(cell, norm(x[t[std::size_t((e + 1) % 3)]] - x[t[std::size_t(e)]]));
  const Vec3 ext = box.hi - box.lo;
  while ((ext.x / cell + 1) * (ext.y / cell + 1) * (ext.z / cell + 1) >
         Real(8 * set_.size() + 4096))
    cell = std::max(cell * Real(1.25), std::numeric_limits<Real>::min());  // as UniformGrid
  grid_ = {box.lo, cell, std::int64_t(ext.x / cell) + 1, std::int64_t(ext.y / cell) + 1,
           std::int64_t(ext.z / cell) + 1};
  const std::int64_t nx = grid_.nx, ny = grid_.ny, nz = grid_.nz;
  auto clampi = [](std::int64_t i, std::int64_t n) {
    return std::clamp<std::int64_t>(i, 0, n - 1);
  };
  auto cell_range = [&](const Vec3& lo, const Vec3& hi, std::array<std::int64_t, 6>& c) {
    c = {clampi(std::int64_t(std::floor((lo.x - box.lo.x) / cell)), nx),
         clampi(std::int64_t(std::floor((hi.x - box.lo.x) / cell)), nx),
         clampi(std::int64_t(std::floor((lo.y - box.lo.y) / cell)), ny),
         clampi(std::int64_t(std::floor((hi.y - box.lo.y) / cell)), ny),
         clampi(std::int64_t(std::floor((lo.z - box.lo.z) / cell)), nz),
         clampi(std::int64_t(std::floor((hi.z - box.lo.z) / cell)), nz)};
  };
  const auto cells = std::size_t(nx * ny * nz);
  const Vec3 grow{grow_by, grow_by, grow_by};
  boxes_.resize(tris_.size());
  for (std::size_t t = 0; t < tris_.size(); ++t) {
    const auto& tri = tris_[t];
    Vec3 lo = x[tri[0]], hi = x[tri[0]];
    for (int k = 1; k < 3; ++k) {
      const Vec3& p = x[tri[std::size_t(k)]];
      lo = {std::min(lo.x, p.x), std::min(lo.y, p.y), std::min(lo.z, p.z)};
      hi = {std::max(hi.x, p.x), std::max(hi.y, p.y), std::max(hi.z, p.z)};
    }
    boxes_[t] = {lo, hi};
  }
  auto each_cell = [&](std::size_t t, auto&& fn) {
    std::array<std::int64_t, 6> c;
    const Vec3 g = grow_each ? Vec3{grow_each[t], grow_each[t], grow_each[t]} : grow;
    cell_range(boxes_[t][0] - g, boxes_[t][1] + g, c);
    each_cell_in(c[0], c[1], c[2], c[3], c[4], c[5], nx, ny, fn);
  };
  bin_primitives(cells, tris_.size(), only, cell_start_, cell_tris_, each_cell);
}

// Whether triangle `tri` is point k's own neighbourhood: for a colliding particle, its corners
// within the exclusion's radius; for a fixed or driven probe, the points it shares a face with
// (radius one link or more), and any face with no free corner (nothing of the pair moves).
bool TriangleProximity::excluded(std::int64_t k, const std::array<std::uint32_t, 3>& tri,
                                 const TopologicalExclusion* exclusion) const {
  if (std::size_t(k) < free_count_) {
    if (exclusion)
      for (const std::uint32_t c : tri)
        if (local_[c] >= 0 && exclusion->excluded(std::uint32_t(k), std::uint32_t(local_[c])))
          return true;
    return false;
  }
  if (local_[tri[0]] < 0 && local_[tri[1]] < 0 && local_[tri[2]] < 0) return true;
  if (!exclusion || exclusion->radius() < 1) return false;
  const std::size_t r = std::size_t(k) - free_count_;
  const auto first = ring_points_.begin() + ring_start_[r],
             last = ring_points_.begin() + ring_start_[r + 1];
  for (const std::uint32_t c : tri)
    if (std::binary_search(first, last, c)) return true;
  return false;
}

template <class F>
void TriangleProximity::touch(std::int64_t k, std::uint32_t t, const Vec3* x, Real radius,
                              F&& fn) const {
  const std::uint32_t p = set_[std::size_t(k)];
  const auto& tri = tris_[t];
  const std::array<Real, 3> w = closest_weights(x[p], x[tri[0]], x[tri[1]], x[tri[2]]);
  const Vec3 closest = x[tri[0]] * w[0] + x[tri[1]] * w[1] + x[tri[2]] * w[2];
  const Vec3 d = x[p] - closest;
  const Real d2 = dot(d, d);
  if (d2 < radius * radius && d2 != 0) fn(t, w, d, d2);
}

// Calls fn(t, w, d, d2) for every triangle t of particle k's cell closer than `radius` (d: from
// the closest point, weights w, to the particle), that is neither the particle's own nor, by
// `exclusion`, its neighbourhood.
template <class F>
void TriangleProximity::near(std::int64_t k, const Vec3* x, Real radius,
                             const TopologicalExclusion* exclusion, F&& fn) const {
  auto clampi = [](std::int64_t i, std::int64_t n) {
    return std::clamp<std::int64_t>(i, 0, n - 1);
  };
  const std::uint32_t p = set_[std::size_t(k)];
  const Vec3 q = (x[p] - grid_.lo) / grid_.cell;
  const auto c = std::size_t(
      (clampi(std::int64_t(q.z), grid_.nz) * grid_.ny + clampi(std::int64_t(q.y), grid_.ny)) *
          grid_.nx +
      clampi(std::int64_t(q.x), grid_.nx));
  // A triangle whose box is farther than the radius along an axis is farther than the radius:
  // six compares before the closest point's divisions, which most of a cell's triangles fail.
  // The slack (a thousandth of the radius) keeps every pair the exact test would keep, whatever
  // the closest point's rounding: the same pairs as without the test.
  const Real g = radius * Real(1.001);
  const Vec3 xp = x[p];
  for (std::uint32_t s = cell_start_[c]; s < cell_start_[c + 1]; ++s) {
    const std::uint32_t t = cell_tris_[s];
    const auto& box = boxes_[t];
    if (xp.x < box[0].x - g || xp.x > box[1].x + g || xp.y < box[0].y - g || xp.y > box[1].y + g ||
        xp.z < box[0].z - g || xp.z > box[1].z + g)
      continue;
    const auto& tri = tris_[t];
    if (tri[0] == p || tri[1] == p || tri[2] == p) continue;
    touch(k, t, x, radius, [&](std::uint32_t, const auto& w, const Vec3& d, Real d2) {
      if (!excluded(k, tri, exclusion)) fn(t, w, d, d2);
    });
  }
}

bool TriangleProximity::near_holds(const Vec3* x, Real radius, Real reach,
                                   const TopologicalExclusion* exclusion) const {
  if (near_reach_ != reach || near_exclusion_ != exclusion) return false;
  // A pair's distance changed by at most the particle's move plus its corners' largest.
  return 2 * largest_move(x, tracked_, anchor_) <= reach - radius;
}

bool TriangleProximity::find_near(const Vec3* x, Real reach, const TopologicalExclusion* exclusion,
                                  int threads) {
  bin(x, reach);
  const std::size_t cap = start_lists(per_thread_near_, thread_full_, threads, max_contacts_);
  const auto n = static_cast<std::int64_t>(set_.size());
#pragma omp parallel for schedule(dynamic, 256) num_threads(threads) if (threads > 1)
  for (std::int64_t k = 0; k < n; ++k) {
    auto& list = per_thread_near_[std::size_t(thread_id())];
    near(k, x, reach, exclusion, [&](std::uint32_t t, const auto&, const Vec3&, Real) {
      if (list.size() >= cap) {
        thread_full_[std::size_t(thread_id())] = 1;
        return;
      }
      list.push_back({std::uint32_t(k), t});
    });
  }
  for (const std::uint8_t t : thread_full_) near_off_ = near_off_ || t != 0;
  if (near_off_) return false;
  collision::room_for_any_split(per_thread_near_, cap);
  near_.clear();
  for (const auto& list : per_thread_near_) near_.insert(near_.end(), list.begin(), list.end());
  take_anchor(x, tracked_, anchor_);
  near_reach_ = reach;
  near_exclusion_ = exclusion;
  return true;
}

// Each pair's reach, radius + its margin (at most max_margin, at least kMinMarginFraction
// radius, else kMotionFactor h times the particle's largest speed relative to a corner), is at
// most the triangle's share plus the particle's: a speed relative to a corner is at most the sum
// of the two speeds relative to the mean of the tracked points. So the grid is searched for each
// pair's own motion, not for the fastest point's (the cloth's resting parts stay in small
// cells while its sides swing): the same candidates. A thousandth more keeps them whatever the
// rounding.
void TriangleProximity::take_shares(const Vec3* v, Real radius, Real h, Real max_margin) {
  Vec3 mean{};
  for (const std::uint32_t p : tracked_) mean += v[p];
  mean = mean * (Real(1) / Real(std::max<std::size_t>(tracked_.size(), 1)));
  constexpr Real kSlack = Real(1.001);
  tri_share_.resize(tris_.size());
  for (std::size_t t = 0; t < tris_.size(); ++t) {
    Real u2 = 0;
    for (const std::uint32_t c : tris_[t]) u2 = std::max(u2, norm2(v[c] - mean));
    tri_share_[t] = kSlack * std::min(radius + max_margin, radius + kMinMarginFraction * radius +
                                                               kMotionFactor * h * std::sqrt(u2));
  }
  particle_share_.resize(set_.size());
  for (std::size_t k = 0; k < set_.size(); ++k)
    particle_share_[k] = kSlack * std::min(max_margin, kMotionFactor * h * norm(v[set_[k]] - mean));
}

// Calls fn(t, d2) for every triangle t within the shares of particle k and t (take_shares),
// neither the particle's own nor, by `exclusion`, its neighbourhood; d2: the squared distance.
// The particle visits the cells its box (grown by its share) overlaps, a triangle lies in those
// its box grown by its share overlaps, and a pair is taken in one cell only: the one holding
// the low corner of the two grown boxes' overlap.
template <class R, class F>
void TriangleProximity::near_grown(std::int64_t k, const Vec3* x,
                                   const TopologicalExclusion* exclusion, R&& reach, F&& fn) const {
  const std::uint32_t p = set_[std::size_t(k)];
  const Vec3 xp = x[p];
  const Real a = particle_share_[std::size_t(k)];
  const Vec3 plo = xp - Vec3{a, a, a}, phi = xp + Vec3{a, a, a};
  const auto c0 = cell_at(plo), c1 = cell_at(phi);
  for (std::int64_t cz = c0[2]; cz <= c1[2]; ++cz)
    for (std::int64_t cy = c0[1]; cy <= c1[1]; ++cy)
      for (std::int64_t cx = c0[0]; cx <= c1[0]; ++cx) {
        const auto c = std::size_t((cz * grid_.ny + cy) * grid_.nx + cx);
        for (std::uint32_t s = cell_start_[c]; s < cell_start_[c + 1]; ++s) {
          const std::uint32_t t = cell_tris_[s];
          const Real g = tri_share_[t];
          const Vec3 lo = boxes_[t][0] - Vec3{g, g, g}, hi = boxes_[t][1] + Vec3{g, g, g};
          if (phi.x < lo.x || plo.x > hi.x || phi.y < lo.y || plo.y > hi.y || phi.z < lo.z ||
              plo.z > hi.z)
            continue;
          const auto& tri = tris_[t];
          if (tri[0] == p || tri[1] == p || tri[2] == p) continue;
          // The pair's own reach, at most the two shares: the particle's distance to the
          // triangle's box, a lower bound of its distance to the triangle, rejects most pairs
          // before the cell test and the closest point.
          const Real r = std::min(g + a, reach(t));
          const auto& b = boxes_[t];
          if (xp.x < b[0].x - r || xp.x > b[1].x + r || xp.y < b[0].y - r || xp.y > b[1].y + r ||
              xp.z < b[0].z - r || xp.z > b[1].z + r)
            continue;
          const Vec3 corner{std::max(plo.x, lo.x), std::max(plo.y, lo.y), std::max(plo.z, lo.z)};
          if (cell_at(corner) != std::array<std::int64_t, 3>{cx, cy, cz}) continue;
          const std::array<Real, 3> w = closest_weights(xp, x[tri[0]], x[tri[1]], x[tri[2]]);
          const Vec3 d = xp - (x[tri[0]] * w[0] + x[tri[1]] * w[1] + x[tri[2]] * w[2]);
          const Real d2 = dot(d, d);
          if (!(d2 < r * r) || d2 == 0) continue;
          if (!excluded(k, tri, exclusion)) fn(t, d2);
        }
      }
}

std::array<std::int64_t, 3> TriangleProximity::cell_at(const Vec3& p) const {
  const Vec3 q = (p - grid_.lo) / grid_.cell;
  auto clampi = [](Real a, std::int64_t n) {
    return std::clamp<std::int64_t>(std::int64_t(std::floor(a)), 0, n - 1);
  };
  return {clampi(q.x, grid_.nx), clampi(q.y, grid_.ny), clampi(q.z, grid_.nz)};
}

void TriangleProximity::candidates(const Vec3* x, const Vec3* v, Real radius, Real h,
                                   Real max_margin, const TopologicalExclusion* exclusion,
                                   int threads, std::vector<std::array<std::uint32_t, 4>>& out) {
  out.clear();
  full_ = false;
  if (tris_.empty() || set_.empty()) return;
  take_shares(v, radius, h, max_margin);
  Real mean_share = 0;
  for (const Real g : tri_share_) mean_share += g;
  bin(x, mean_share / Real(tri_share_.size()), nullptr, tri_share_.data());
  const std::size_t cap = start_lists(per_thread_candidates_, thread_full_, threads, max_contacts_);
  const auto n = static_cast<std::int64_t>(set_.size());
#pragma omp parallel for schedule(dynamic, 256) num_threads(threads) if (threads > 1)
  for (std::int64_t k = 0; k < n; ++k) {
    auto& list = per_thread_candidates_[std::size_t(thread_id())];
    const std::uint32_t p = set_[std::size_t(k)];
    // The pair's reach: the radius and its margin, from the largest speed of the particle
    // relative to a corner.
    auto reach = [&](std::uint32_t t) {
      Real closing2 = 0;
      for (const std::uint32_t c : tris_[t]) closing2 = std::max(closing2, norm2(v[p] - v[c]));
      return radius + pair_margin(radius, h, closing2, max_margin);
    };
    near_grown(k, x, exclusion, reach, [&](std::uint32_t t, Real) {
      const auto& tri = tris_[t];
      if (list.size() >= cap) {  // refused below, as apply's contacts are
        thread_full_[std::size_t(thread_id())] = 1;
        return;
      }
      list.push_back({p, tri[0], tri[1], tri[2], t});
    });
  }
  for (const std::uint8_t t : thread_full_) full_ = full_ || t != 0;
  if (full_) return;
  collision::room_for_any_split(per_thread_candidates_, cap);  // any thread may find them all
  // (particle, triangle) order: the same candidates in the same order whatever the threads.
  all_candidates_.clear();
  for (const auto& list : per_thread_candidates_)
    all_candidates_.insert(all_candidates_.end(), list.begin(), list.end());
  std::sort(all_candidates_.begin(), all_candidates_.end(), [](const auto& a, const auto& b) {
    return std::tie(a[0], a[4]) < std::tie(b[0], b[4]);
  });
  for (const auto& c : all_candidates_) out.push_back({c[0], c[1], c[2], c[3]});
}

void TriangleProximity::candidates_near(const Vec3* x, const std::uint8_t* moved, Real reach,
                                        const TopologicalExclusion* exclusion,
                                        std::vector<std::array<std::uint32_t, 4>>& out) {
  out.clear();
  full_ = false;
  if (tris_.empty() || set_.empty()) return;
  all_candidates_.clear();
  auto keep = [&](std::int64_t k) {
    return [&, k](std::uint32_t t, const auto&, const Vec3&, Real) {
      const auto& tri = tris_[t];
      all_candidates_.push_back({set_[std::size_t(k)], tri[0], tri[1], tri[2], t});
    };
  };
  // The moved particles against every triangle; then every particle against the triangles with
  // a moved corner, alone in the grid (most particles' cells are empty).
  bool any = false;
  for (std::size_t k = 0; k < set_.size() && !any; ++k) any = moved[set_[k]] != 0;
  if (any) {
    bin(x, reach);
    for (std::size_t k = 0; k < set_.size(); ++k)
      if (moved[set_[k]]) near(std::int64_t(k), x, reach, exclusion, keep(std::int64_t(k)));
  }
  moved_tris_.clear();
  for (std::size_t t = 0; t < tris_.size(); ++t)
    if (moved[tris_[t][0]] || moved[tris_[t][1]] || moved[tris_[t][2]])
      moved_tris_.push_back(std::uint32_t(t));
  if (!moved_tris_.empty()) {
    bin(x, reach, &moved_tris_);
    for (std::size_t k = 0; k < set_.size(); ++k)
      near(std::int64_t(k), x, reach, exclusion, keep(std::int64_t(k)));
  }
  std::sort(all_candidates_.begin(), all_candidates_.end(), [](const auto& a, const auto& b) {
    return std::tie(a[0], a[4]) < std::tie(b[0], b[4]);
  });
  all_candidates_.erase(std::unique(all_candidates_.begin(), all_candidates_.end()),
                        all_candidates_.end());
  if (all_candidates_.size() > max_contacts_) {
    full_ = true;
    return;
  }
  for (const auto& c : all_candidates_) out.push_back({c[0], c[1], c[2], c[3]});
}

std::uint64_t TriangleProximity::apply(const Vec3* x, const Vec3* v, Vec3* f,
                                       const TriangleResponse& r,
                                       const TopologicalExclusion* exclusion, int threads) {
  full_ = false;
  all_.clear();  // energy() reads the contacts of the last pass, none when it stops early
  if (tris_.empty() || set_.empty()) return 0;
  const Real reach = r.radius * (1 + kSkinFraction);
  const bool listed = !near_off_ && (near_holds(x, r.radius, reach, exclusion) ||
                                     find_near(x, reach, exclusion, threads));
  if (!listed) bin(x, r.radius);
  // Each particle against its listed triangles, or those of its cell. Each thread keeps at most
  // its share of the contacts: beyond it, the pass goes on without collecting and is refused
  // below.
  const std::size_t cap = start_lists(per_thread_, thread_full_, threads, max_contacts_);
  const auto n = static_cast<std::int64_t>(listed ? near_.size() : set_.size());
#pragma omp parallel for schedule(dynamic, 256) num_threads(threads) if (threads > 1)
  for (std::int64_t i = 0; i < n; ++i) {
    auto& out = per_thread_[std::size_t(thread_id())];
    if (thread_full_[std::size_t(thread_id())]) continue;
    const std::int64_t k = listed ? std::int64_t(near_[std::size_t(i)][0]) : i;
    const std::uint32_t p = set_[std::size_t(k)];
    auto contact = [&](std::uint32_t t, const std::array<Real, 3>& w, const Vec3& d, Real d2) {
      const auto& tri = tris_[t];
      const Real dist = std::sqrt(d2);
      const Vec3 nrm = d / dist;
      const Vec3 vq = v[tri[0]] * w[0] + v[tri[1]] * w[1] + v[tri[2]] * w[2];
      const Vec3 dv = v[p] - vq;
      // The shared law (contact_laws.glsl), as the implicit solvers' terms evaluate it.
      Vec3 force = law::stencil_contact_force(d, dv, r.stiffness, r.damping, r.radius);
      if (r.friction > 0) {
        const Vec3 vt = dv - nrm * dot(dv, nrm);
        const Real speed = norm(vt);
        force -=
            vt * (r.friction * std::abs(dot(force, nrm)) / std::max(speed, kSelfCollisionSlip));
      }
      const Feature fe = feature_of(tri, t, w);
      if (out.size() >= cap) {
        thread_full_[std::size_t(thread_id())] = 1;
        return;
      }
      out.push_back({p, t, fe.kind, fe.a, fe.b, force, w, r.radius - dist});
    };
    if (listed)
      touch(k, near_[std::size_t(i)][1], x, r.radius, contact);
    else
      near(k, x, r.radius, exclusion, contact);
  }
  for (const std::uint8_t t : thread_full_) full_ = full_ || t != 0;
  if (full_) return 0;
  collision::room_for_any_split(per_thread_, cap);  // next time (thread_lists.hpp)
  // Applied in (particle, feature, triangle) order: the same sums whatever the threads. A
  // particle touching an edge or a corner shared by several triangles is pushed once (else a
  // particle resting on a flat mesh would feel 2 k on an edge and up to 6 k on a corner).
  all_.clear();
  for (const auto& list : per_thread_) all_.insert(all_.end(), list.begin(), list.end());
  auto key = [](const Contact& c) { return std::tuple{c.particle, c.kind, c.a, c.b, c.triangle}; };
  std::sort(all_.begin(), all_.end(),
            [&](const Contact& a, const Contact& b) { return key(a) < key(b); });
  all_.erase(std::unique(all_.begin(), all_.end(),
                         [](const Contact& a, const Contact& b) {
                           return a.particle == b.particle && a.kind == b.kind && a.a == b.a &&
                                  a.b == b.b;
                         }),
             all_.end());
  for (const Contact& c : all_) {
    f[c.particle] += c.force;
    const auto& tri = tris_[c.triangle];
    for (int k = 0; k < 3; ++k) f[tri[std::size_t(k)]] -= c.force * c.weight[std::size_t(k)];
  }
  return all_.size();
}

bool TriangleProximity::bound_motion(const Vec3* x, Real share, Real radius, Real* bound) const {
  if (near_off_ || near_reach_ < 0) return tris_.empty();
  for (const auto& [k, t] : near_) {
    const std::uint32_t p = set_[k];
    const auto& tri = tris_[t];
    const std::array<Real, 3> w = closest_weights(x[p], x[tri[0]], x[tri[1]], x[tri[2]]);
    const Real d = norm(x[p] - (x[tri[0]] * w[0] + x[tri[1]] * w[1] + x[tri[2]] * w[2]));
    const Real b = law::stencil_bound(share, d, radius, kStencilFloor);
    bound[p] = std::min(bound[p], b);
    for (const std::uint32_t c : tri) bound[c] = std::min(bound[c], b);
  }
  return true;
}

double TriangleProximity::energy(Real stiffness) const {
  double e = 0;
  for (const Contact& c : all_) e += 0.5 * double(stiffness) * double(c.gap) * double(c.gap);
  return e;
}

}  // namespace maille::collision
