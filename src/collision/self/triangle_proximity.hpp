// Point-triangle proximity (primitive = "triangles"): a particle closer than s to a triangle of
// the colliding surface that is not its own neighbourhood is pushed out along the direction from
// the closest point of the triangle, and the triangle's corners take the reaction by their
// barycentric weights. A coarse cloth then cannot pass through itself between its particles:
// particle-particle contacts alone need a radius of about the cloth's spacing for that.
//
// Triangles are binned into a grid of cells (their boxes grown by s); each particle tests the
// triangles of its cell. Contacts are collected per thread, sorted by (particle, triangle) and
// applied in that order: deterministic whatever the thread count.
//
// The explicit pass (apply) keeps the particle-triangle pairs within radius + skin (a Verlet
// list, skin = kSkinFraction radius) and tests only those while no colliding point has moved
// more than skin / 2 since they were found: a pair then cannot have come from beyond the reach
// to within the radius (a triangle's points move no farther than its corners). The contacts,
// and so the forces, are the same as a full search's, bit for bit.
//
// Contacts are bounded like the particle pairs (self_collision_engine.hpp): a pass that would
// collect more than `max_contacts` is stopped and flagged (full()), and the stage refuses it by
// name, rather than a radius taking in every triangle ending in std::bad_alloc inside a parallel
// region.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "exclusion.hpp"
#include "maille/model.hpp"

namespace maille::collision {

// Closest point of triangle abc to p, as barycentric weights (law::triangle_closest_weights,
// include/maille/detail/contact_laws.glsl): exact zeros outside the touched feature.
std::array<Real, 3> closest_weights(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c);

// The feature of a triangle that a closest point lies on: a face (kind 2, a = the triangle's
// index), an edge (kind 1, its two corners a < b) or a corner (kind 0, a). Triangles sharing an
// edge or a corner give it the same feature.
struct Feature {
  std::uint32_t kind = 0, a = 0, b = 0;
  bool operator==(const Feature&) const = default;
};
Feature feature_of(const std::array<std::uint32_t, 3>& tri, std::uint32_t triangle,
                   const std::array<Real, 3>& w);

struct TriangleResponse {
  Real radius = 0, stiffness = 0, damping = 0, friction = 0;
};

class TriangleProximity {
 public:
  // `set`: the colliding particles (global ids, sorted); triangles: the model's faces whose
  // corners all belong to `groups_mask` (1 for points of the colliding groups); at most
  // `max_contacts` contacts in a pass (see kBytesPerContact). The fixed and driven points of the
  // groups probe the faces too, as particles do (their force is written, as a fixed corner's is:
  // a [[listen]] of the force at such a point hears the cloth's push; nothing moves them).
  TriangleProximity(const Model& m, const std::vector<std::uint32_t>& set,
                    const std::vector<std::uint8_t>& groups_mask, std::size_t max_contacts);
  // Adds the forces; returns the number of particle-triangle contacts. `exclusion` (may be
  // null) removes triangles whose free corners are topological neighbours of the particle.
  // When the pass found more than `max_contacts`, no force is added and full() is true.
  std::uint64_t apply(const Vec3* x, const Vec3* v, Vec3* f, const TriangleResponse& r,
                      const TopologicalExclusion* exclusion, int threads);
  // The particle-triangle pairs that may touch during a step of h (the same tests as apply's,
  // without forces): closer than the contact radius plus the pair's own margin, kMotionFactor h
  // times the particle's largest speed relative to the triangle's corners (at least
  // kMinMarginFraction radius, at most max_margin; broad_phase.hpp). A pair moving together (a flat
  // cloth's particle and its far triangles while it falls) is not a candidate. {particle, corners},
  // sorted by particle then triangle. For implicit schemes (TriangleContacts). More than
  // max_contacts candidates: none, and full() is true.
  void candidates(const Vec3* x, const Vec3* v, Real radius, Real h, Real max_margin,
                  const TopologicalExclusion* exclusion, int threads,
                  std::vector<std::array<std::uint32_t, 4>>& out);
  // The particle-triangle pairs of the `moved` points (mask by global id) within `reach` at x: a
  // moved particle against every triangle, every particle against the triangles with a moved
  // corner (a solver's search again around the points past their drift limit). {particle,
  // corners}, sorted by particle then triangle. More than max_contacts: none, and full().
  void candidates_near(const Vec3* x, const std::uint8_t* moved, Real reach,
                       const TopologicalExclusion* exclusion,
                       std::vector<std::array<std::uint32_t, 4>>& out);
  // The potential 1/2 k (radius - d)^2 of the contacts the last apply() pushed.
  double energy(Real stiffness) const;
  // After apply() at x: for every pair of its Verlet list, `share` times the particle-triangle
  // distance beyond the pair's floor (law::stencil_bound, kStencilFloor of `radius`) bounds the
  // particle's and the corners' moves (bound: by global id, lowered only).
  // Every pair off the list is farther than the radius at x (the list holds while no point has
  // moved more than its skin's half). False when the last pass had no list (over the budget).
  bool bound_motion(const Vec3* x, Real share, Real radius, Real* bound) const;
  std::size_t triangles() const { return tris_.size(); }
  bool full() const { return full_; }
  std::size_t max_contacts() const { return max_contacts_; }

 private:
  struct Contact {
    std::uint32_t particle, triangle;
    // The feature touched: a face (kind 2: the triangle), an edge (kind 1: its two corners) or a
    // corner (kind 0). Triangles sharing the touched edge or corner count it once.
    std::uint32_t kind, a, b;
    Vec3 force;                  // on the particle
    std::array<Real, 3> weight;  // barycentric weights of the closest point
    Real gap;                    // radius - distance, m (> 0)
  };
  struct Grid {
    Vec3 lo{};
    Real cell = 1;
    std::int64_t nx = 1, ny = 1, nz = 1;
  };
  // The triangles (those of `only` when given) into the grid, their boxes grown by `grow`.
  // `grow_each` (may be null): each triangle's own growth instead (`grow` then sizes the cells).
  void bin(const Vec3* x, Real grow, const std::vector<std::uint32_t>* only = nullptr,
           const Real* grow_each = nullptr);
  // candidates(): each triangle's and each particle's share of a pair's reach.
  void take_shares(const Vec3* v, Real radius, Real h, Real max_margin);
  // reach(t): the pair's own reach (at most the two shares).
  template <class R, class F>
  void near_grown(std::int64_t k, const Vec3* x, const TopologicalExclusion* exclusion, R&& reach,
                  F&& fn) const;
  std::array<std::int64_t, 3> cell_at(const Vec3& p) const;  // floor, clamped to the grid
  // Whether near_ (found at anchor_ within `reach`) still holds every pair within `radius`.
  bool near_holds(const Vec3* x, Real radius, Real reach,
                  const TopologicalExclusion* exclusion) const;
  // near_: the pairs within `reach` now; false (near_off_ set) when they overflow the budget.
  bool find_near(const Vec3* x, Real reach, const TopologicalExclusion* exclusion, int threads);
  // Calls fn(t, w, d, d2) when particle k (local) is closer than `radius` to triangle t.
  template <class F>
  void touch(std::int64_t k, std::uint32_t t, const Vec3* x, Real radius, F&& fn) const;
  template <class F>
  void near(std::int64_t k, const Vec3* x, Real radius, const TopologicalExclusion* exclusion,
            F&& fn) const;

  Grid grid_;
  std::vector<std::array<std::uint32_t, 3>> tris_;  // global corner ids
  // The colliding particles (the first free_count_, sorted), then the fixed and driven points
  // of the groups (sorted), which probe the faces as particles do.
  std::vector<std::uint32_t> set_;
  std::size_t free_count_ = 0;
  std::vector<std::uint32_t> ring_start_, ring_points_;  // per probe: who shares a face with it
  bool excluded(std::int64_t k, const std::array<std::uint32_t, 3>& tri,
                const TopologicalExclusion* exclusion) const;
  std::vector<std::int32_t> local_;  // global id -> index in set_, -1 when not colliding
  std::vector<Vec3> xs_;             // the particles' positions, gathered each pass
  std::vector<std::uint32_t> cell_start_, cell_tris_;
  std::vector<std::array<Vec3, 2>> boxes_;  // [triangles] each one's box at the last bin()
  std::vector<std::vector<Contact>> per_thread_;
  std::vector<std::uint8_t> thread_full_;  // [threads] 1: that thread's list reached its cap
  std::vector<Contact> all_;
  // {particle, corners, triangle} per thread, then all of them sorted
  std::vector<std::vector<std::array<std::uint32_t, 5>>> per_thread_candidates_;
  std::vector<std::array<std::uint32_t, 5>> all_candidates_;
  std::vector<std::uint32_t> moved_tris_;
  std::vector<Real> tri_share_,
      particle_share_;  // take_shares()  // candidates_near(): the triangles with a moved corner
  std::size_t max_contacts_;
  bool full_ = false;
  // apply's Verlet list: {local particle, triangle} pairs within near_reach_ of each other at
  // the positions anchor_ (of tracked_: the particles and the triangles' corners)
  std::vector<std::vector<std::array<std::uint32_t, 2>>> per_thread_near_;
  std::vector<std::array<std::uint32_t, 2>> near_;
  std::vector<std::uint32_t> tracked_;
  std::vector<Vec3> anchor_;
  Real near_reach_ = -1;  // -1: no list yet
  const TopologicalExclusion* near_exclusion_ = nullptr;
  bool near_off_ = false;  // the list overflowed the budget once: a full search every pass

 public:
  // Memory per contact, for the budget: a thread's list and the merged list, each with the
  // slack of a growing vector (up to twice its size).
  static constexpr std::size_t kBytesPerContact = 4 * sizeof(Contact);
  // apply's skin over the radius: 0.5 found again after a 1/4 radius move (a 1.5e-4 s step
  // moves a point falling at 3 m/s 0.45 mm: every few steps for an 8 mm layer), the list
  // about 1.5^2 as long as the contacts on a flat layer.
  static constexpr Real kSkinFraction = Real(0.5);
};

}  // namespace maille::collision
