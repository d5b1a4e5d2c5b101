// The broad phases of self-collision. Each finds every unordered pair of particles closer than
// r exactly once, tests it (distance, then exclusion) and records close pairs into the calling
// thread's sink, in both orders. They differ only in how they avoid testing far pairs.
//
//   brute          all n (n - 1) / 2 pairs (the reference)
//   UniformGrid    cells of size c >= r over the bounding box, particles counting-sorted into
//                  them; each cell meets itself and its 13 "forward" neighbours (half of the
//                  26), so each pair of cells is visited once
//   HashedGrid     the same cells, hashed into 2n buckets (memory follows the particles, not
//                  the box); a particle checks its own cell and 13 forward neighbours by exact
//                  cell coordinates, so hash collisions cost time, never a duplicate or a miss
//   Octree         the hierarchical grid: Morton-sorted particles split into up to 8 children
//                  while a node holds more than a leaf's worth and is wider than r; a dual
//                  traversal visits node pairs whose boxes are closer than r
#pragma once

#ifdef _OPENMP
#include <omp.h>
#endif

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

#include "exclusion.hpp"
#include "maille/detail/csr.hpp"
#include "maille/vec3.hpp"

namespace maille::collision {

// The rows of a grid's cells listing the primitives (edges, triangles) that overlap each
// (detail::build_rows): every one of the `count` primitives, or those of `only` when given;
// each_cell(p, fn) calls fn(cell) for each cell that primitive p overlaps.
template <class Index, class Value, class EachCell>
void bin_primitives(std::size_t cells, std::size_t count, const std::vector<std::uint32_t>* only,
                    std::vector<Index>& cell_start, std::vector<Value>& cell_items,
                    EachCell&& each_cell) {
  detail::build_rows(cells, cell_start, cell_items, [&](auto&& emit) {
    auto bin = [&](std::size_t p) { each_cell(p, [&](std::size_t c) { emit(c, p); }); };
    if (only)
      for (const std::uint32_t p : *only) bin(std::size_t(p));
    else
      for (std::size_t p = 0; p < count; ++p) bin(p);
  });
}

// A list of pairs found at a reach holds while its points stay near where they were then: their
// positions (x[points[i]]) into `anchor` when it is found, and the largest move since.
inline void take_anchor(const Vec3* x, const std::vector<std::uint32_t>& points,
                        std::vector<Vec3>& anchor) {
  anchor.resize(points.size());
  for (std::size_t i = 0; i < points.size(); ++i) anchor[i] = x[points[i]];
}
inline Real largest_move(const Vec3* x, const std::vector<std::uint32_t>& points,
                         const std::vector<Vec3>& anchor) {
  Real moved2 = 0;
  for (std::size_t i = 0; i < points.size(); ++i)
    moved2 = std::max(moved2, norm2(x[points[i]] - anchor[i]));
  return std::sqrt(moved2);
}

// Calls fn((k ny + j) nx + i) for the cells (i, j, k) of a grid nx cells wide and ny deep with
// i0 <= i <= i1, j0 <= j <= j1, k0 <= k <= k1 (k, then j, then i).
template <class Fn>
void each_cell_in(std::int64_t i0, std::int64_t i1, std::int64_t j0, std::int64_t j1,
                  std::int64_t k0, std::int64_t k1, std::int64_t nx, std::int64_t ny, Fn&& fn) {
  for (std::int64_t k = k0; k <= k1; ++k)
    for (std::int64_t j = j0; j <= j1; ++j)
      for (std::int64_t i = i0; i <= i1; ++i) fn(std::size_t((k * ny + j) * nx + i));
}

// The margin that implicit schemes' contact candidates add to a contact distance s (the
// self-collision pairs, [[contact]] pairs, point-triangle pairs): kMotionFactor h times the
// largest relevant speed (the step's start speed, with a quarter more room for the solve's
// corrections, and twice for two points closing in), at least kMinMarginFraction s (a resting
// model would otherwise find its candidates again at every sub-millimetre move).
inline constexpr Real kMotionFactor = Real(2.5);
inline constexpr Real kMinMarginFraction = Real(0.25);

// A stencil pair's margin (point-triangle, edge-edge): kMotionFactor h times its closing speed
// (the square root of `closing2`, the largest squared speed of a point of one relative to a
// point of the other), at least kMinMarginFraction s, at most `max_margin`.
inline Real pair_margin(Real s, Real h, Real closing2, Real max_margin) {
  return std::min(max_margin,
                  std::max(kMinMarginFraction * s, kMotionFactor * h * std::sqrt(closing2)));
}

// The calling thread's index in its OpenMP team (0 outside a parallel region): its sink.
inline int thread_id() {
#ifdef _OPENMP
  return omp_get_thread_num();
#else
  return 0;
#endif
}

struct Sink {
  std::vector<std::uint32_t> pairs;  // a, b, b, a, ... (close pairs, both orders)
  std::uint64_t tested = 0, excluded = 0, skipped = 0;
  // At most `cap` entries: a pair beyond it is dropped and `full` set, and the caller refuses
  // the pass (an allocation failing inside an OpenMP region would abort the process).
  std::size_t cap = ~std::size_t{0};
  bool full = false;
  void clear() { pairs.clear(), tested = excluded = skipped = 0, full = false; }
};

// Close partners per point gathered from the threads' sinks (both orders of each pair) into
// rows, each sorted: point a's partners are partners[start[a] .. start[a + 1]). The same order
// whatever thread found which pair. Buffers keep their capacity (no allocation once warm).
struct PartnerRows {
  std::vector<std::uint32_t> start, partners;  // CSR: point a's partners (sorted)
  void build(const std::vector<Sink>& sinks, std::size_t points);
  std::size_t pairs() const { return partners.size() / 2; }
};

// The motion margin of the points `set` over a step of h: kMotionFactor h times their largest
// speed relative to their mean velocity (a common motion, a fall under gravity included, brings
// no pair closer), or relative to rest when `absolute`.
Real motion_margin(const Vec3* v, const std::vector<std::uint32_t>& set, Real h,
                   bool absolute = false);

struct Query {
  const Vec3* x = nullptr;  // [n] positions of the colliding particles
  std::uint32_t n = 0;
  Real r = 0;                                       // contact distance
  const TopologicalExclusion* exclusion = nullptr;  // null: nothing excluded
  bool signatures = false;                          // skip cell pairs by signatures
  // Contacts between two groups (group_contact.cpp): per particle, bit 0 its side and bit 1
  // "fixed". Null: every pair counts. Otherwise a pair counts only across the sides and with at
  // least one free end; other pairs are skipped before the distance test (not counted tested).
  const std::uint8_t* tag = nullptr;
};

inline bool skipped_by_tag(const Query& q, std::uint32_t a, std::uint32_t b) {
  if (!q.tag) return false;
  const unsigned ta = q.tag[a], tb = q.tag[b];
  return ((ta ^ tb) & 1u) == 0 || (ta & tb & 2u) != 0;
}

inline void test_pair(const Query& q, std::uint32_t a, std::uint32_t b, Sink& s) {
  if (skipped_by_tag(q, a, b)) return;
  ++s.tested;
  const Vec3 d = q.x[b] - q.x[a];
  if (dot(d, d) >= q.r * q.r) return;
  if (q.exclusion && q.exclusion->excluded(a, b)) {
    ++s.excluded;
    return;
  }
  if (s.pairs.size() + 4 > s.cap) {
    s.full = true;
    return;
  }
  s.pairs.push_back(a), s.pairs.push_back(b), s.pairs.push_back(b), s.pairs.push_back(a);
}

// Sinks: one per thread (resized by the callers to the thread count). Each pass leaves every
// sink room for all the pairs it found (thread_lists.hpp): which thread finds which pairs is
// up to the dynamic schedule.
void brute_pairs(const Query& q, std::vector<Sink>& sinks, int threads);

struct Box {
  Vec3 lo, hi;
};
Box bounds(const Vec3* x, std::uint32_t n);

class UniformGrid {
 public:
  // Returns the cell size used: c, or larger when the box would need more than the cell budget
  // (max(8 n, 4096) cells), so memory stays O(n).
  Real find(const Query& q, Real c, std::vector<Sink>& sinks, int threads);
  std::uint64_t occupied() const { return occupied_.size(); }

 private:
  std::vector<std::uint32_t> cell_of_, start_, order_, occupied_;
  std::vector<CellSignature> sig_;
};

class HashedGrid {
 public:
  Real find(const Query& q, Real c, std::vector<Sink>& sinks, int threads);
  std::uint64_t occupied() const { return occupied_; }

 private:
  std::vector<std::uint32_t> bucket_of_, start_, cursor_, order_;
  std::vector<std::int32_t> coords_;  // [3 n] cell coordinates, by particle
  std::vector<std::int32_t> cell_;    // [3 n] cell coordinates, in sorted order
  std::vector<CellSignature> sig_;
  std::uint64_t occupied_ = 0;
};

class Octree {
 public:
  void find(const Query& q, std::vector<Sink>& sinks, int threads);
  std::uint64_t occupied() const { return leaves_; }
  // The leaves' boxes after the last find (for drawing).
  std::vector<Box> leaf_boxes() const;

 private:
  struct Node {
    std::uint32_t begin = 0, end = 0;       // range in order_
    std::uint32_t child = 0, children = 0;  // first child index, count (0: leaf)
    Box box;
    CellSignature sig;
  };
  std::uint32_t build(std::uint32_t idx, std::uint32_t begin, std::uint32_t end, int level,
                      const Query& q);
  void self(std::uint32_t a, const Query& q, Sink& s) const;
  void pair(std::uint32_t a, std::uint32_t b, const Query& q, Sink& s) const;
  void tasks(std::uint32_t a, std::uint32_t b, std::size_t want);
  bool far(const Node& a, const Node& b, Real r) const;

  std::vector<std::uint64_t> code_, key_scratch_;
  std::vector<std::uint32_t> order_, order_scratch_, count_;
  std::vector<Node> nodes_;
  std::vector<std::pair<std::uint32_t, std::uint32_t>> tasks_;  // (a, a): self; (a, b): pair
  std::uint64_t leaves_ = 0;
};

}  // namespace maille::collision
