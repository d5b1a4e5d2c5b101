// One step's contacts, found once by the contact stages and read by every implicit solver.
//
// Under an implicit scheme a contact stage does not add a force in the step's force pass: it
// finds its contacts once per step, at its reach plus the step's motion margin (so that a solve
// that moves points by a whole step still sees every contact that comes within reach), and puts
// its typed arrays into the ContactSet (Stage::find_contacts). The solvers then evaluate the set
// themselves, by the same pure laws (detail/link_laws.glsl, detail/contact_laws.glsl): at the
// step's start for the right-hand side and the residual, and at every iterate inside the solve.
// No solver subtracts a force another pass computed, and no broad phase runs twice in a step.
//
//   kind            stored as (the stage's own arrays)               law
//   point-point     LinkPool of conditional contact links            link_laws.glsl
//                   (self-collision particles, [[contact]] pairs):   contact_normal_law,
//                   ids, law parameters, lagged friction             conditional spring
//   point-triangle, TriangleContacts: {particle, corners} then       contact_laws.glsl
//   edge-edge       {edge, edge} candidates, law, lagged friction
//   point-obstacle  PointContacts: the stage's points and its        the shape's penalty
//                   shape's placement, lagged friction
//
// The explicit schemes do not read the set: their stages' apply() evaluates the same laws over
// lists found at reach plus a skin (the self-collision Verlet lists) in the force pass.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <span>
#include <vector>

#include "maille/mat3.hpp"
#include "maille/vec3.hpp"

namespace maille {

class LinkPoolBase;

// Point-obstacle contacts: a point against something an implicit solve does not move, evaluated
// by the solve at its iterates: vertex block descent evaluates them at every iterate (force and 3x3
// stiffness per point), matrix-free CG adds their stiffness to its diagonal blocks.
class PointContacts {
 public:
  virtual ~PointContacts() = default;
  // The obstacle's placement at time t: the end of the step for the solve, its start when a
  // solver evaluates the set at x_n (its right-hand side, its residual). Ends any lag (below):
  // the terms are then exactly the stage's explicit force law.
  virtual void set_time(double t) = 0;
  // Lagged friction: the normal force and the normal of each point's contact are taken at
  // (x, v) and the current placement (the step's start), then the placement moves to t_next;
  // they are held for the solve until the next set_time (so sticking is a smooth, convex term
  // of the solve). Stages without friction only move the placement.
  virtual void lag(std::span<const std::uint32_t> /*points*/, const Vec3* /*x*/, const Vec3* /*v*/,
                   double t_next) {
    set_time(t_next);
  }
  // For each point i of `points` that the stage collides: adds the contact force at x[i], v[i]
  // into f[i] and its stiffness -d f / d x - (1/h) d f / d v (positive semi-definite) into
  // hessian[i], and sets touching[i] = 1 where a contact acts (when `touching` is not null:
  // solvers watch steps that start or end a contact, where the force jumps). Points are
  // independent: threads may run disjoint point sets at once.
  virtual void add_terms(std::span<const std::uint32_t> points, const Vec3* x, const Vec3* v,
                         Real inv_h, Vec3* f, Mat3* hessian, std::uint8_t* touching) const = 0;
  // The contact's elastic push on point p at x, at rest relative to the obstacle (no damper, no
  // friction): zero where p touches nothing. Solvers let a Newton step leave a contact whole
  // only when it does not move against this push (a point sliding off a sphere leaves it; one
  // pressed through a thin box or between a conditional obstacle's samples does not).
  virtual Vec3 push(std::uint32_t /*p*/, const Vec3& /*x*/) const { return {}; }
  // The thinnest contact region the stage has, m (a box's smallest side, a conditional
  // obstacle's threshold; +inf for a half-space): a point moving further than half of it in a
  // step could cross it unseen, so solvers test such a point's segment at that spacing.
  virtual Real thickness() const { return std::numeric_limits<Real>::infinity(); }
};

// One stencil's coupling in an assembled matrix (TriangleContacts::couplings): its four points,
// their coefficients c and the block B, so that block (i, j) is c_i c_j B.
struct StencilCoupling {
  std::array<std::uint32_t, 4> ids{};
  std::array<Real, 4> c{};
  Mat3 block;
};

// Stencil contacts: a point and a triangle, or two edges, of moving points (self-collision with
// primitive = "triangles"). A candidate is the particle and the triangle's
// three corners, found at the step's start within the contact radius plus the step's motion.
// Its energy is the penalty on the point-triangle distance d, E = k (s - d)^2 / 2 while d < s,
// the closest point q = sum w_j x_j found again at every evaluation, with the damper along the
// normal n = (x_p - q) / d: the force on the particle is F = n (k (s - d) - z n.(v_p - v_q)) and
// corner j takes -w_j F. Roles: 0 the particle (coefficient c = 1), 1 to 3 the corners
// (c = -w_j). A contact on an edge or a corner shared by several of the particle's candidates
// counts once (the lowest triangle), as in the explicit force. Friction stays explicit.
// A stencil pair's floor, as a fraction of its radius: the conservative bounds keep a pair found
// farther apart than the floor from coming nearer (law::stencil_bound).
inline constexpr Real kStencilFloor = Real(0.001);

class TriangleContacts {
 public:
  virtual ~TriangleContacts() = default;
  // This step's candidates: {particle, corner, corner, corner}, sorted by particle.
  virtual std::span<const std::array<std::uint32_t, 4>> candidates() const = 0;
  // The forces at x, v of every candidate in contact, into f (all four points).
  virtual void accumulate(const Vec3* x, const Vec3* v, Vec3* f) const = 0;
  // Candidate e's point-triangle distance at x (unsigned: a point that crossed the face is
  // pushed on through it, so solvers keep each point's motion within a fraction of its
  // distances at the step's start; see implicit_vbd.hpp, "conservative bounds").
  virtual Real distance(std::size_t e, const Vec3* x) const = 0;
  // The contact radius s, m: a candidate acts while its distance is below it (solvers leave out
  // of their sweeps the candidates too far to act before they find them again).
  virtual Real radius() const = 0;
  // Whether candidate e acts at any distance this step (friction lagged from the step's start,
  // held wherever the points go): solvers keep it in their sweeps however far it is.
  virtual bool held(std::size_t /*e*/) const { return false; }
  // For each point i of `points`: the candidates entries[row[i]] .. entries[row[i + 1] - 1],
  // each `candidate * 4 + role`: the force on i into f[i] and the stiffness block
  // c^2 (k + z inv_h) n n^T (the energy's Gauss-Newton Hessian, with the damper through
  // v = (x - x_n) / h) into hessian[i]. Points are independent: threads may run disjoint sets.
  virtual void add_point_terms(std::span<const std::uint32_t> points, const std::uint32_t* row,
                               const std::uint32_t* entries, const Vec3* x, const Vec3* v,
                               Real inv_h, Vec3* f, Mat3* hessian) const = 0;
  // Where a sweep started: the points there and each candidate's distance() there (null: no
  // start). add_point_terms may then skip a candidate whose distance cannot have come down to
  // the radius since (each side's points moved less than the margin): the same terms, less work.
  virtual void set_sweep_start(const Vec3* /*x*/, const Real* /*distances*/) {}
  // Linear solvers: keeps the normals of the contacts active at (x, v) ...
  virtual void linearise(const Vec3* x, const Vec3* v) = 0;
  // ... and adds (a k + b z) sum c c^T n n^T u over them into out (one thread) ...
  virtual void apply(Real a, Real b, const Vec3* u, Vec3* out) const = 0;
  // ... and their diagonal blocks (a k + b z) c_i^2 n n^T into diagonal ...
  virtual void add_diagonal(Real a, Real b, Mat3* diagonal) const = 0;
  // ... and each active candidate's coupling for an assembled matrix: block (i, j) of the
  // stencil is c_i c_j B, B = (a k + b z) n n^T plus friction's b-scaled tangent block, appended
  // to out.
  virtual void couplings(Real a, Real b, std::vector<StencilCoupling>& out) const = 0;
  // The search's guarantee beyond its candidates (re-detection, docs/implicit.md,
  // "Intersection-free cloth: what holds"): the pairs of the stage's points that are not
  // candidates (nor excluded) cannot meet while every point of points() (its colliding particles
  // and the fixed or driven corners of its faces) stays within drift_limit() of its predicted
  // place plus one displacement common to them all. The prediction: at the step's search, the
  // point's place there moved by h times its velocity there; after a search again inside the
  // step, its place at that search. A solver that would take a free point farther searches
  // again first (ForceEvaluator::find_contacts_again). +inf: no such guarantee (the default).
  virtual Real drift_limit() const { return std::numeric_limits<Real>::infinity(); }
  virtual std::span<const std::uint32_t> points() const { return {}; }
};

// The step's contacts as the solvers read them: views of the stages' typed arrays, refilled at
// every step's force pass under an implicit scheme (the vectors keep their capacity: no
// allocation once warm).
class ContactSet {
 public:
  void clear() {
    pairs_.clear();
    stencils_.clear();
    obstacles_.clear();
  }
  void add(const LinkPoolBase& pairs) { pairs_.push_back(&pairs); }
  void add(TriangleContacts& stencils) { stencils_.push_back(&stencils); }
  void add(PointContacts& obstacle) { obstacles_.push_back(&obstacle); }

  // Point-point pairs as conditional links (ids, law parameters and lagged friction per pair).
  std::span<const LinkPoolBase* const> pairs() const { return pairs_; }
  // Point-triangle and edge-edge candidates, per stage.
  std::span<TriangleContacts* const> stencils() const { return stencils_; }
  // Point-obstacle contacts, per obstacle stage.
  std::span<PointContacts* const> obstacles() const { return obstacles_; }
  bool empty() const { return pairs_.empty() && stencils_.empty() && obstacles_.empty(); }

  // The force of every contact of the set that acts at (x, v), added into f: the pairs and
  // stencils over their candidates, the obstacles over `points` at the placement their last
  // set_time or lag left (`inv_h` scales their damper's block, written into the scratch
  // `blocks`, sized like x and overwritten).
  void add_forces(std::span<const std::uint32_t> points, const Vec3* x, const Vec3* v, Real inv_h,
                  Vec3* f, Mat3* blocks) const;

 private:
  std::vector<const LinkPoolBase*> pairs_;
  std::vector<TriangleContacts*> stencils_;
  std::vector<PointContacts*> obstacles_;
};

}  // namespace maille
