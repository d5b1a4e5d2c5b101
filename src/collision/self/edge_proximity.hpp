// Edge-edge proximity (primitive = "triangles"): two edges of the colliding surface that share
// no corner and come closer than s are pushed apart along the line joining their closest points
// (unless a closest point is a particle's corner: law::edge_edge_acts)
// (include/maille/detail/contact_laws.glsl: the parameters, the interior rule, the penalty).
// Point-triangle contacts see a particle against a face; a wrung or folded cloth also makes edges
// cross edges with every corner far from every face, which only this sees.
//
// Edges (each once, from the groups' faces) are binned into a grid by their boxes grown by the
// reach plus half the longest edge; each edge tests the edges of the cell of its midpoint with a
// larger index (a pair closer than the reach is found there, once). Pairs are kept sorted by
// (edge, edge): the forces are summed in that order whatever the thread count.
//
// The explicit pass keeps a Verlet list of the pairs within radius + skin, as
// TriangleProximity does, and tests only those while no corner has moved more than skin / 2.
// Contacts are bounded by the memory budget like the other self-collision lists (full()).
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "broad_phase.hpp"
#include "exclusion.hpp"
#include "maille/model.hpp"
#include "triangle_proximity.hpp"

namespace maille::collision {

class EdgeProximity {
 public:
  // `set`: the colliding particles (global ids, sorted); `faces`: the colliding faces (global
  // corner ids); `topological_radius`: R of [self_collision]. Every edge of the faces takes part
  // (a fixed border too); a pair with no corner in `set` is never tested (nothing of it moves).
  EdgeProximity(const Model& m, const std::vector<std::uint32_t>& set,
                const std::vector<std::array<std::uint32_t, 3>>& faces, int topological_radius,
                std::size_t max_contacts);
  // Adds the forces of the edge pairs in contact; returns their number. `exclusion` (may be
  // null) removes pairs with a corner of one a topological neighbour of a corner of the other.
  std::uint64_t apply(const Vec3* x, const Vec3* v, Vec3* f, const TriangleResponse& r,
                      const TopologicalExclusion* exclusion, int threads);
  // The pairs that may touch during a step of h: closer than the radius plus the pair's margin
  // (kMotionFactor h times the largest speed of a corner of one relative to a corner of the
  // other, at least kMinMarginFraction radius, at most max_margin), appended to `out` as
  // {a0, a1, b0, b1}, in (edge, edge) order, with which corners are colliding particles
  // appended to `particles` (bit j for corner j: law::edge_edge_acts). None and full() when over
  // the budget.
  void candidates(const Vec3* x, const Vec3* v, Real radius, Real h, Real max_margin,
                  const TopologicalExclusion* exclusion, int threads,
                  std::vector<std::array<std::uint32_t, 4>>& out,
                  std::vector<std::uint8_t>& particles);
  // The pairs with an edge of a `moved` point (mask by global id) within `reach` at x, as
  // candidates() gives them (TriangleProximity::candidates_near).
  void candidates_near(const Vec3* x, const std::uint8_t* moved, Real reach,
                       const TopologicalExclusion* exclusion, int threads,
                       std::vector<std::array<std::uint32_t, 4>>& out,
                       std::vector<std::uint8_t>& particles);
  // The potential 1/2 k (radius - d)^2 of the contacts the last apply() pushed.
  double energy(Real stiffness) const;
  // After apply() at x: for every pair of its Verlet list, `share` times the segments' distance
  // beyond the pair's floor bounds the four corners' moves (bound: by global id, lowered only); as
  // TriangleProximity::bound_motion. False when the last pass had no list.
  bool bound_motion(const Vec3* x, Real share, Real radius, Real* bound) const;
  std::size_t edges() const { return edges_.size(); }
  bool full() const { return full_; }
  std::size_t max_contacts() const { return max_contacts_; }

  // Every corner of the faces touches the faces as a point (a colliding particle, or a fixed or
  // driven point of the groups probing them: TriangleProximity), so an edge pair whose closest
  // point is an edge's end is left to that point's face contacts (law::edge_edge_acts): the
  // four "particle" bits are always set.
  static constexpr std::uint8_t kPointCorners = 0xF;

  static constexpr std::size_t kBytesPerContact =
      4 * (2 * sizeof(std::uint32_t) + 6 * sizeof(Real));

 private:
  struct Contact {
    std::uint32_t a, b;  // edge indices, a < b
    Vec3 force;          // on edge a's closest point
    Real s, t, gap;      // the closest points' parameters; radius - distance
  };
  // A pair's own reach in candidates(): the radius plus its margin (pair_margin) from its
  // corners' velocities.
  struct PairReach {
    const Vec3* v;
    Real radius, h, max_margin;
    Real of(const std::array<std::uint32_t, 2>& a, const std::array<std::uint32_t, 2>& b) const;
  };
  // Every pair (a < b) closer than `reach` into `out` (sorted); false when over the budget.
  // `grow` (may be null): per edge, a share of the reach such that a pair farther than the sum
  // of its edges' shares is not wanted (boxes farther apart are skipped before any distance).
  // `only` (may be null): only the pairs with one of those edges (they alone are binned, and
  // every edge looks for them). `pair_reach` (may be null): a pair closer than the smaller of
  // `reach` and its own reach.
  bool find_pairs(const Vec3* x, Real reach, const TopologicalExclusion* exclusion, int threads,
                  std::vector<std::array<std::uint32_t, 2>>& out, const Real* grow = nullptr,
                  const std::vector<std::uint32_t>* only = nullptr,
                  const PairReach* pair_reach = nullptr);
  void bin(const Vec3* x, Real grow, const std::vector<std::uint32_t>* only = nullptr);
  std::size_t cell_of(const Vec3& p) const;
  bool moves(const std::array<std::uint32_t, 2>& a, const std::array<std::uint32_t, 2>& b) const;
  bool excluded(std::uint32_t a, std::uint32_t b, const TopologicalExclusion* exclusion) const;
  bool pairs_hold(const Vec3* x, Real radius, Real reach,
                  const TopologicalExclusion* exclusion) const;

  std::vector<std::array<std::uint32_t, 2>> edges_;  // global corner ids, lower first
  std::vector<std::int32_t> local_;                  // global id -> index in the set, -1
  std::vector<std::uint32_t> corners_;               // every edge corner, sorted (tracked moves)
  std::vector<Vec3> anchor_;                         // corners_' positions when pairs_ was found
  Real pairs_reach_ = -1;                            // -1: pairs_ not found yet
  const TopologicalExclusion* pairs_exclusion_ = nullptr;
  // The grid: origin, cell, counts, and the edges of each cell (counting sort).
  Vec3 lo_{};
  Real cell_ = 1;
  std::int64_t nx_ = 1, ny_ = 1, nz_ = 1;
  std::vector<std::uint32_t> cell_start_, cell_edges_;
  std::vector<Box> boxes_;           // [edges] each edge's box at the last search
  std::vector<Real> grow_;           // [edges] candidates(): each edge's share of a pair's reach
  std::vector<std::uint32_t> from_;  // candidates_near(): the edges with a moved corner
  std::vector<std::vector<std::array<std::uint32_t, 2>>> per_thread_pairs_;
  std::vector<std::array<std::uint32_t, 2>> pairs_;       // apply's Verlet list
  std::vector<std::array<std::uint32_t, 2>> wide_pairs_;  // candidates' search
  std::vector<std::vector<Contact>> per_thread_;
  std::vector<Contact> all_;
  std::vector<std::uint8_t> thread_full_;
  std::size_t max_contacts_;
  int radius_links_ = 0;  // R: with R >= 1, edges with corners joined by a face edge never meet
  bool full_ = false;
  bool linked(std::uint32_t p, std::uint32_t q) const;  // p-q is an edge of the faces
};

}  // namespace maille::collision
