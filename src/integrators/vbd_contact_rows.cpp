// Vertex block descent's contact rows (implicit_vbd.hpp): the model's links and the step's
// contacts by point (CSR rows), the conservative bounds, the candidates near enough to act and
// their compaction for the sweeps, and the greedy colouring of the points' graph.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <functional>
#include <limits>

#include "implicit_vbd.hpp"
#include "maille/colouring.hpp"
#include "maille/detail/csr.hpp"
#include "maille/link_set.hpp"
#include "maille/shared_laws.hpp"

namespace maille {

namespace {

// The guess's largest motion times this is the contact margin (2: two points moving toward
// each other; 1.25: room before a refresh is needed).
constexpr Real kMarginFactor = Real(2.5);
// The smallest margin, m: a resting model (no motion) would otherwise find its candidates again
// at the first sub-micron move.
constexpr Real kMinMargin = Real(1e-4);
// Each point's allowance (how far it may go from x_n before the sweeps' compacted contacts are
// taken again) is its motion so far times this: room before a new compaction is needed.
constexpr Real kRoom = Real(1.25);
// No allowance is below this fraction of the largest one: a point at rest that starts to move
// would otherwise make the solve find its candidates again at once.
constexpr Real kFloorFraction = Real(0.25);
// The smallest allowance, m: a resting model (no motion) would otherwise find its candidates
// again at the first sub-micron move.
constexpr Real kMinAllowance = Real(5e-5);

// The links `slots` of a pool by point: row[i] .. row[i + 1] - 1 index out, in slot order.
void csr_from_slots(std::span<const LinkEnds> ends, std::size_t n,
                    std::span<const std::uint32_t> slots, std::vector<std::uint32_t>& row,
                    std::vector<std::uint32_t>& out) {
  detail::build_rows(n, row, out, [&](auto&& emit) {
    for (const std::uint32_t l : slots) {
      emit(ends[l].a, l);
      emit(ends[l].b, l);
    }
  });
}
}  // namespace

void VertexBlockDescent::rows_from_slots(PoolRows& r, std::size_t n,
                                         std::span<const std::uint32_t> slots) {
  csr_from_slots(r.pool->slot_ends(), n, slots, r.row, r.slots);
}

void VertexBlockDescent::build_static_rows(const Model& m) {
  const std::size_t n = points_;
  const auto pools = m.links.pools();
  rows_.resize(pools.size());
  model_dynamic_ = false;
  for (std::size_t p = 0; p < pools.size(); ++p) {
    PoolRows& r = rows_[p];
    r.pool = pools[p].get();
    r.fixed = !r.pool->conditional();
    model_dynamic_ = model_dynamic_ || !r.fixed;
    if (!r.fixed) continue;
    scratch_.resize(r.pool->size());
    for (std::size_t l = 0; l < scratch_.size(); ++l) scratch_[l] = std::uint32_t(l);
    rows_from_slots(r, n, scratch_);
  }
  free_.clear();
  for (std::uint32_t i = 0; i < n; ++i)
    if (m.points.inv_mass[i] > 0) free_.push_back(i);
  static_ready_ = true;
  coloured_ = false;
  coarse_.reset();
  if (settings_.coarse == VbdCoarse::aggregates) coarse_.build(m, free_, n);
  direction_.assign(n, Vec3{});
}

void conservative_bounds(std::span<TriangleContacts* const> contacts, const Vec3* x,
                         std::vector<Real>& bound, std::vector<std::vector<Real>>* gaps) {
  std::fill(bound.begin(), bound.end(), std::numeric_limits<Real>::infinity());
  if (gaps && gaps->size() < contacts.size()) gaps->resize(contacts.size());
  for (std::size_t k = 0; k < contacts.size(); ++k) {
    const TriangleContacts* t = contacts[k];
    const auto cand = t->candidates();
    if (gaps) (*gaps)[k].resize(cand.size());
    for (std::size_t e = 0; e < cand.size(); ++e) {
      const Real d = t->distance(e, x);
      if (gaps) (*gaps)[k][e] = d;
      const Real b = law::stencil_bound(kBoundFraction, d, t->radius(), kStencilFloor);
      for (const std::uint32_t p : cand[e]) bound[p] = std::min(bound[p], b);
    }
  }
}

// Conservative bounds of this step's contacts: point-triangle candidates, and the stages'
// point-point contact pairs (each point of a pair moves at most kBoundFraction of their
// distance: they close at most 0.8 of it per update, so neither jumps over the other's
// contact shell, nor a layer of points spaced within the contact radius). Without them, at 1/60 s
// and 10 sweeps, cloth_heap's folds crossed in 311 triangle pairs, cloth_in_bowl's in 21 and
// flag_storm's in 8; with them 120, 0 and 0 (tests/physics/test_large_steps.cpp).
void VertexBlockDescent::take_bounds(const Model& m, const Vec3* x) {
  conservative_bounds(triangle_contacts_, x, bound_, &gaps_);
  const std::size_t model_pools = m.links.pools().size();
  for (std::size_t p = 0; p < transient_pools_; ++p)
    for (const LinkEnds& e : rows_[model_pools + p].pool->slot_ends()) {
      const Real b = kBoundFraction * norm(x[e.a] - x[e.b]);
      bound_[e.a] = std::min(bound_[e.a], b);
      bound_[e.b] = std::min(bound_[e.b], b);
    }
}

// Each stage's candidates by point, every role (a corner's row holds the candidates whose
// triangle it is a corner of): all of them (row, entries; the colouring's graph), or with
// `kept`, only the kept ones (the sweeps' rows).
void VertexBlockDescent::candidate_rows(const TriangleRows& t,
                                        const std::vector<std::uint8_t>* kept,
                                        std::vector<std::uint32_t>& row,
                                        std::vector<std::uint32_t>& entries) const {
  const auto cand = t.contacts->candidates();
  detail::build_rows(points_, row, entries, [&](auto&& emit) {
    for (std::size_t e = 0; e < cand.size(); ++e)
      if (!kept || (*kept)[e])
        for (std::uint32_t role = 0; role < 4; ++role)
          emit(cand[e][role], std::uint32_t(e * 4 + role));
  });
}

void VertexBlockDescent::triangle_rows(std::span<TriangleContacts* const> contacts) {
  if (triangles_.size() < contacts.size()) triangles_.resize(contacts.size());
  triangle_stages_ = contacts.size();
  for (std::size_t k = 0; k < contacts.size(); ++k) {
    TriangleRows& t = triangles_[k];
    t.contacts = contacts[k];
    candidate_rows(t, nullptr, t.row, t.entries);
  }
}

// The contacts near enough to act before any point has gone further than its allowance from
// x_n (take_allowances, from the motion of x): the model's conditional links, the stages'
// contact links (found by the stage at its own, wider, margin) and their point-triangle
// candidates, each within its reach plus its points' allowances at x_n (a point-triangle
// distance moves by at most the particle's motion plus its corners' largest). A candidate left
// out cannot act while every point stays within its allowance; the solve finds the candidates
// again as soon as one does not (beyond_allowance: solve(), residual()). The sweeps then load
// only these: on the 64^2 drape the stage's pairs and triangles within a few centimetres were
// a fifth of the step, nearly all far. The conservative bounds still take every candidate
// (take_bounds): a far one bounds a step as before.
void VertexBlockDescent::find_candidates(const Model& m, const Vec3* x, Real margin) {
  const std::size_t model_pools = m.links.pools().size();
  for (std::size_t p = 0; p < rows_.size(); ++p) {
    PoolRows& r = rows_[p];
    if (r.fixed) continue;
    scratch_.clear();
    if (p < model_pools) {
      r.pool->near_slots(x, margin, scratch_);
    } else {
      for (std::size_t l = 0; l < r.pool->size(); ++l) scratch_.push_back(std::uint32_t(l));
    }
    rows_from_slots(r, points_, scratch_);
  }
  margin_ = margin;
}

void VertexBlockDescent::compact(const Vec3* x) {
  take_allowances(x);
  const Vec3* xn = xn_.data();
  for (PoolRows& r : rows_) {
    if (r.fixed) continue;
    scratch_.clear();
    if (r.pool->conditional()) {
      r.pool->near_slots(xn, allow_.data(), scratch_);
    } else {  // a stage's links of a kind always active: all of them act
      for (std::size_t l = 0; l < r.pool->size(); ++l) scratch_.push_back(std::uint32_t(l));
    }
    csr_from_slots(r.pool->slot_ends(), points_, scratch_, r.swept_row, r.swept_slots);
  }
  for (std::size_t k = 0; k < triangle_stages_; ++k) {
    TriangleRows& t = triangles_[k];
    const auto cand = t.contacts->candidates();
    const Real radius = t.contacts->radius();
    t.kept.assign(cand.size(), 0);
    for (std::size_t e = 0; e < cand.size(); ++e) {
      // A candidate's gap changes by at most the two largest moves among its four points
      // (a particle and a triangle's corner, or a corner of each edge).
      const auto& c = cand[e];
      std::array<Real, 4> a{allow_[c[0]], allow_[c[1]], allow_[c[2]], allow_[c[3]]};
      std::partial_sort(a.begin(), a.begin() + 2, a.end(), std::greater<>());
      const Real reach = radius + a[0] + a[1];
      t.kept[e] = t.contacts->held(e) || t.contacts->distance(e, xn) < reach;
    }
    candidate_rows(t, &t.kept, t.swept_row, t.swept_entries);
  }
  compacted_ = true;
  candidates_ = candidates_swept_ = 0;
  for (const PoolRows& r : rows_)
    if (!r.fixed) {
      candidates_ += r.pool->size();
      candidates_swept_ += r.swept_slots.size() / 2;  // each link is in both its points' rows
    }
  for (std::size_t t = 0; t < triangle_stages_; ++t) {
    candidates_ += triangles_[t].kept.size();
    candidates_swept_ += triangles_[t].swept_entries.size() / 4;
  }
}

// Greedy colouring in point order: a point takes the smallest colour none of its coloured
// neighbours holds. Fixed points are never moved, so links to them constrain nothing.
void VertexBlockDescent::colour() {
  const std::size_t n = points_;
  colour_of_.assign(n, kUncoloured);
  const std::uint32_t colours =
      colour_points(free_, colour_of_, stamp_, [&](std::uint32_t i, auto&& visit) {
        for (const PoolRows& r : rows_) {
          const auto ends = r.pool->slot_ends();
          for (std::uint32_t k = r.row[i]; k < r.row[i + 1]; ++k) {
            const LinkEnds e = ends[r.slots[k]];
            visit(e.a == i ? e.b : e.a);
          }
        }
        for (std::size_t t = 0; t < triangle_stages_; ++t) {  // a candidate's four points
          const TriangleRows& r = triangles_[t];
          const auto cand = r.contacts->candidates();
          for (std::uint32_t k = r.row[i]; k < r.row[i + 1]; ++k)
            for (const std::uint32_t j : cand[r.entries[k] / 4])
              if (j != i) visit(j);
        }
      });
  detail::build_rows(colours, colour_row_, by_colour_, [&](auto&& emit) {
    for (const std::uint32_t i : free_) emit(colour_of_[i], i);
  });
  arrange_lanes();
}

Real VertexBlockDescent::largest_motion(const Vec3* x) const {
  Real d2 = 0;
  for (const std::uint32_t i : free_) d2 = std::max(d2, norm2(x[i] - xn_[i]));
  return std::sqrt(d2);
}

// Per point: kRoom times its motion from x_n at x, at least kFloorFraction of the largest and
// kMinAllowance; fixed and driven points take the largest (their motion is the drive's).
void VertexBlockDescent::take_allowances(const Vec3* x) {
  const Real largest = std::max(kRoom * largest_motion(x), kMinAllowance);
  const Real floor = std::max(kFloorFraction * largest, kMinAllowance);
  std::fill(allow_.begin(), allow_.end(), largest);
  for (const std::uint32_t i : free_) allow_[i] = std::max(kRoom * norm(x[i] - xn_[i]), floor);
}

Real VertexBlockDescent::margin_for(const Vec3* x) const {
  return std::max(kMarginFactor * largest_motion(x), kMinMargin);
}

bool VertexBlockDescent::beyond_allowance(const Vec3* x) const {
  for (const std::uint32_t i : free_)
    if (norm2(x[i] - xn_[i]) > allow_[i] * allow_[i]) return true;
  return false;
}

}  // namespace maille
