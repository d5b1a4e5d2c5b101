// Internal: re-detection inside an implicit step (offset geometric contact's second half, for
// the solvers: docs/implicit.md, "Intersection-free cloth: what holds").
//
// A stencil stage's search finds every pair of its points within its radius plus a margin; the
// pairs it leaves out cannot meet while each free point stays within the stage's
// drift_limit() of its predicted place (TriangleContacts::drift_limit). The guard keeps that
// ball per point: a solver asks hold() for each move, a move that would leave the ball ends on
// it, and the solver has the stages search again (ForceEvaluator::find_contacts_again) before it
// moves the points any farther. Balls are convex, so a point that moves on segments between
// places inside its ball never leaves it, whatever order the solver takes the points in.
#pragma once

#include <cmath>
#include <cstdint>
#include <limits>
#include <span>
#include <vector>

#include "maille/contact_set.hpp"
#include "maille/model.hpp"

namespace maille {

class DriftGuard {
 public:
  // After the step's search at (x, v): point i's prediction is x_i + h v_i plus the common
  // displacement (take_common). Inactive without a stage that keeps a drift limit.
  void first_search(std::span<TriangleContacts* const> stencils, const Model& m, const Vec3* x,
                    const Vec3* v, Real h);
  // After a search again at x: each point is predicted where it is, with no common part.
  void searched_again(const Vec3* x);
  // The points to search again around at x (Stage::find_contacts_again's `moved`): those held
  // since the last search and those past kRenewShare of their limit (renewed with them, they
  // are not held a sweep later, and their later moves are not cut short at a ball's edge), or
  // none (search everywhere) when they are more than kNearShare of the guarded points (a
  // search around each then costs about as much as one everywhere).
  std::span<const std::uint32_t> moved(const Vec3* x);
  // After a search again around moved() at x: each of them is predicted where it is (its ball
  // about x, radius its limit), the other points keep theirs.
  void searched_near(const Vec3* x);
  bool active() const { return active_; }

  // The displacement common to the stages' points, from where they are (x) against their
  // predictions: the centre of the box of their differences, the fixed and driven points'
  // included with none (a fixed point does not move; a driven one takes its drive's move after
  // the solve, before the next search, as its velocity predicts), drawn back to within the
  // anchors' limit of zero when they are some (an anchor does not move with it). Taken once
  // per search, before the solver's moves from it on (a ball must not move while points move
  // within it).
  void take_common(const Vec3* x);

  // A move of point i from `from` to `to`, held within its ball: `to` when inside, else the
  // point of the segment farthest along it inside the ball, or the segment's point nearest the
  // ball when none is (the move's start may lie outside: VBD's guess starts at x_n, the CG
  // solvers' advance too, while the ball is about the prediction x_n + h v_n). Held moves stay
  // on their segment, so the solvers' conservative bounds on the segment's length still hold;
  // a held move makes a search due.
  Vec3 hold(std::uint32_t i, const Vec3& from, const Vec3& to) {
    const Real limit = limit_[i];
    if (!(limit < kUnguarded) || inside(i, to)) return to;
    return held_move(i, from, to);
  }
  // A move to `at` the solver takes whole: a search is due when it leaves point i's ball.
  void note(std::uint32_t i, const Vec3& at) {
    if (!inside(i, at)) held_[i] = 1;
  }
  // Whether `at` lies within point i's ball (moves that may be skipped: extrapolation, coarse).
  bool inside(std::uint32_t i, const Vec3& at) const {
    const Real limit = limit_[i];
    return !(limit < kUnguarded) || norm2(at - predicted_[i] - common_) <= limit * limit;
  }
  // Whether a move was held since the last search (then the solver searches before moving on).
  bool search_due() const;
  // Searches again inside this step, for the solvers' counters.
  int searches_again() const { return searches_again_; }
  // Measured on cloth_heap_vbd, wrung_cloth and cloth_on_sphere_vbd (docs/implicit.md): renewing
  // at half the limit left points lagging at their balls' edge (2 mm into the floor under the
  // heap, against 0.3 mm with every point renewed at each search); a third keeps 0.39 mm.
  static constexpr double kNearShare = 0.25;
  static constexpr Real kRenewShare = Real(1) / 3;

 private:
  static constexpr Real kUnguarded = std::numeric_limits<Real>::infinity();
  Vec3 held_move(std::uint32_t i, const Vec3& from, const Vec3& to);
  void take_limits(std::span<TriangleContacts* const> stencils, const Model& m);
  bool active_ = false;
  int searches_again_ = 0;
  Vec3 common_{};
  std::vector<Real> limit_;      // per point: the smallest drift limit of its stages (+inf: none)
  std::vector<Vec3> predicted_;  // per point: its predicted place
  std::vector<std::uint8_t> held_;
  std::vector<std::uint32_t> guarded_;  // the free points of a limited stage
  std::vector<std::uint32_t> anchors_;  // its fixed and driven points (they share the centre)
  Real anchor_limit_ = kUnguarded;      // the smallest limit of the stages with anchors
  std::vector<std::uint32_t> moved_;    // moved()
};

}  // namespace maille
