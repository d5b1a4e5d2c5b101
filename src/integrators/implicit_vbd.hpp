// Internal: vertex block descent (VBD) for the implicit Euler step, and its force residual
// (implicit_vbd.cpp; the CG solvers measure theirs with step_residual.hpp).
#pragma once

#include <cmath>
#include <cstdint>
#include <span>
#include <string_view>
#include <utility>
#include <vector>

#include "contact_entry.hpp"
#include "drift_guard.hpp"
#include "maille/integrator.hpp"
#include "maille/mat3.hpp"
#include "maille/model.hpp"
#include "maille/state.hpp"
#include "vbd_coarse.hpp"
#include "vbd_lanes.hpp"

namespace maille {

// Conservative bounds (the VBD paper's collision handling): a point-triangle distance is
// unsigned, so a point that one update carried across a face would be pushed on through it.
// Each point that belongs to a point-triangle candidate moves, in one update, at most
// kBoundFraction of the smallest distance of its candidates at the update's start: the particle
// and the triangle then close at most 2 x 0.4 of their gap, and never cross. VBD takes the
// bounds again before every sweep (each point moves once per sweep), so over a step a point
// goes as far as its Newton steps take it, approaching a face geometrically until the contact
// holds it; the CG solvers advance their solved positions in stages the same way
// (implicit_euler.cpp, advance_guarded). bound[i] = +inf for points of no candidate. VBD bounds the
// points of the stages' point-point contact pairs (self-collision with primitive = "points") the
// same way, by their pair distances (VertexBlockDescent::take_bounds).
inline constexpr Real kBoundFraction = Real(0.4);
// `gaps` (may be null): each stage's candidates' distances at x, gaps[stage][candidate].
void conservative_bounds(std::span<TriangleContacts* const> contacts, const Vec3* x,
                         std::vector<Real>& bound, std::vector<std::vector<Real>>* gaps = nullptr);
// `to`, pulled back toward `from` to lie within `bound` of it.
inline Vec3 within_bound(const Vec3& from, const Vec3& to, Real bound) {
  const Vec3 d = to - from;
  const Real len2 = norm2(d);
  return len2 > bound * bound ? from + d * (bound / std::sqrt(len2)) : to;
}

// State memory: v_n of the last step's start (the adaptive guess needs last step's
// acceleration), 3 doubles per point; in the State so that checkpoints resume bit for bit and
// backends take over each other's runs (the GPU's VBD reads and writes the same slot).
inline constexpr std::string_view kVbdMemory = "implicit_euler.vbd";

// The fallback: a sweep whose merit (the sum of g_i . H_i^-1 g_i) grows by more than this factor
// turns the acceleration off for the rest of the step. Chebyshev's extrapolation is not monotone:
// on cloth_on_sphere at 1/60 s the merit rises by less than 2 in most accelerated sweeps of a
// converging step, and a test at 1 (any rise) turned the acceleration off in most steps (10
// sweeps: 30 % stretch against 21 %; factors 2, 4 and none gave the same 21 %).
inline constexpr Real kFallbackGrowth = 2;

// The coarse correction (coarse = "aggregates") runs after every kCoarseEvery-th sweep. Cloth on
// a sphere at 1/60 s with 10 sweeps, largest stretch at 64^2 and 128^2: after every sweep 10.5
// and 10.3 % (twice the corrections' cost), every second 5.6 and 9.1 %, every third 5.8 and 20 %
// (before the final contact rules, docs/implicit.md).
inline constexpr int kCoarseEvery = 2;

// A step across a contact's surface stops within 1/2^kVbdBisections of it (the CPU's solve and
// the GPU's, gpu_obstacle_shaders.cpp).
inline constexpr int kVbdBisections = 10;
// Continuous detection tests at most this many points of a segment (a point faster than this
// many half-thicknesses a step is tested more coarsely).
inline constexpr int kVbdMaxSegmentSamples = 256;

struct VbdResult {
  int sweeps = 0;               // sweeps run this step
  int acceleration_resets = 0;  // sweeps whose residual rose: acceleration turned off
  int colours = 0;              // colours of the point graph (links and this step's contacts)
  int candidate_refreshes = 0;  // contact candidates found again because points moved far
  int coarse_corrections = 0;   // coarse corrections taken (vbd_coarse.hpp)
  // Contact candidates of the step (conditional and stage links, point-triangle candidates) at
  // the last find_candidates, and those near enough to act that the sweeps load.
  std::uint64_t candidates = 0, candidates_swept = 0;
  int searches_again = 0;  // the stages' searches inside the step (a point at its drift limit)
  bool stopped = false;    // a stop was requested between two sweeps: x, v are unfinished
};

// The implicit Euler step as a minimisation (Chen, Macklin et al., "Vertex Block Descent",
// SIGGRAPH 2024; Martin et al. 2011 for the variational form):
//
//   x_n+1 = argmin G(x),  G(x) = sum_i m_i / (2 h^2) |x_i - y_i|^2 + E(x),
//   y_i = x_n,i + h v_n,i + h^2 f_ext,i / m_i,   v_n+1 = (x_n+1 - x_n) / h
//
// E holds every link (and the stages' contacts): a link's force and its Jacobian are the
// gradient and Hessian of its energy, and its dampers see v = (x - x_n) / h, so damping enters
// as the paper's (Rayleigh-like) term through J_v / h with no code of its own. Forces that stay
// explicit (gravity, wind, stages that offer no implicit terms) make up f_ext, taken at the
// step's start; air drag is implicit (a diagonal term). One sweep visits the free points colour
// by colour (no two points of a colour share a link or a contact, so a colour's points are
// updated at once, by threads, without atomics) and moves each by one Newton step on G
// restricted to it: dx_i = H_i^-1 g_i, with g_i = -dG/dx_i = m_i/h^2 (y_i - x_i) + f_i(x) and
// H_i = m_i/h^2 I + sum of its links' blocks (definite mode: positive definite).
class VertexBlockDescent {
 public:
  VertexBlockDescent(const ImplicitSettings& settings, int threads)
      : settings_(settings), threads_(threads) {}

  // Takes the step's start: x_n, v_n and the explicit forces f_ext = s.f() minus the links',
  // the stages' implicit contacts' and the air drag's forces at the start; t_next is the time of
  // the end of the step.
  void begin(const Model& m, const State& s, Real h, double t_next, ForceEvaluator& forces);
  // Solves the step by VBD from s (x, v at the step's start): on exit s.x, s.v hold x_n+1,
  // v_n+1 on free points (fixed points untouched). Needs begin() first.
  VbdResult solve(const Model& m, State& s, Real h);
  // Largest force imbalance |m (v_n+1 - v_n) / h - f(x_n+1, v_n+1)| over free points, divided by
  // m g of the heaviest free point (g = |gravity|, or 9.81 m/s^2 when gravity is off): the
  // residual of the nonlinear implicit Euler equations at s, after a solve.
  double residual(const Model& m, const State& s, Real h);
  // Drops everything sized for a model.
  void reset();
  void set_threads(int threads) { threads_ = threads; }

 private:
  ForceEvaluator* forces_ = nullptr;  // from begin(): asked for stops between sweeps
  struct PoolRows {
    const LinkPoolBase* pool = nullptr;
    std::vector<std::uint32_t> row;    // [points + 1] offsets into slots
    std::vector<std::uint32_t> slots;  // storage slots of the pool's links, by point
    bool fixed = false;                // always-active model pool: rows built once
    // Of those, the links near enough to act (compact()): the sweeps' rows, when not fixed.
    std::vector<std::uint32_t> swept_row, swept_slots;
  };

  // A stage's point-triangle contacts of this step, by point: entries = candidate * 4 + role.
  struct TriangleRows {
    TriangleContacts* contacts = nullptr;
    std::vector<std::uint32_t> row;      // [points + 1]
    std::vector<std::uint32_t> entries;  // candidates' roles, by point
    std::vector<std::uint8_t> kept;      // [candidates] 1: near enough to act (compact())
    std::vector<std::uint32_t> swept_row, swept_entries;  // the kept ones: the sweeps' rows
  };

  void build_static_rows(const Model& m);
  void triangle_rows(std::span<TriangleContacts* const> contacts);
  void take_bounds(const Model& m, const Vec3* x);
  void find_candidates(const Model& m, const Vec3* x, Real margin);
  // The sweeps' rows: of the candidates, those that may act while every point stays within its
  // allowance of x_n, the allowances taken from the motion of x (implicit_vbd.cpp).
  void compact(const Vec3* x);
  void take_allowances(const Vec3* x);
  Real margin_for(const Vec3* x) const;
  void candidate_rows(const TriangleRows& t, const std::vector<std::uint8_t>* kept,
                      std::vector<std::uint32_t>& row, std::vector<std::uint32_t>& entries) const;
  bool beyond_allowance(const Vec3* x) const;
  bool search_again(const Model& m, State& s);
  void rows_from_slots(PoolRows& r, std::size_t n, std::span<const std::uint32_t> slots);
  void colour();
  void point_terms(std::span<const std::uint32_t> points, const Model& m, const Vec3* x,
                   const Vec3* v, Real h, bool skip_kept = false);
  void inertia_terms(std::span<const std::uint32_t> points, const Model& m, const Vec3* x,
                     const Vec3* v, Real h);
  void later_terms(std::span<const std::uint32_t> points, const Vec3* x, const Vec3* v, Real h,
                   std::size_t first_pool, bool skip_kept);
  void arrange_lanes();
  Real sweep(const Model& m, Vec3* x, Vec3* v, Real h);
  void update_block(std::uint32_t colour, std::uint32_t offset, std::uint32_t count, const Model& m,
                    Vec3* x, Vec3* v, Real h);
  void newton_step(std::uint32_t i, const Vec3* x, const Vec3& dx, Real inv_h);
  void initial_guess(const Model& m, State& s, Real h);
  std::pair<Real, Real> contact_change(std::uint32_t i, const Vec3& x0, const Vec3& dx, Real inv_h);
  bool touches_at(std::uint32_t i, const Vec3& at, Real inv_h);
  Real largest_motion(const Vec3* x) const;
  bool leaves_cleanly(std::uint32_t i, const Vec3& from, Real half_thinnest);
  void coarse_terms(const Model& m, const Vec3* x, const Vec3* v, Real h);
  bool coarse_step(const Model& m, Vec3* x, Vec3* v, Real h);
  void extrapolate(int k, Real rho, Real& omega, Vec3* x, Vec3* v, Real h, Real half_thinnest);

  ImplicitSettings settings_;
  int threads_ = 1;
  std::size_t points_ = 0;
  bool static_ready_ = false;
  bool coloured_ = false;       // static models: colours found once
  bool model_dynamic_ = false;  // the model has conditional links
  bool dynamic_ = false;        // conditional or transient links: candidates and colours per step
  std::vector<PoolRows> rows_;  // model pools, then this step's transient pools
  std::vector<std::uint32_t> scratch_;  // candidate slots of one pool
  std::vector<PointContacts*> contacts_;
  std::vector<TriangleRows> triangles_;               // [stages offering point-triangle contacts]
  std::size_t triangle_stages_ = 0;                   // of triangles_, in use this step
  std::vector<TriangleContacts*> triangle_contacts_;  // this step's, as the stages gave them
  std::vector<std::uint32_t> free_;                   // free points, increasing
  std::vector<std::uint32_t> colour_of_;              // [points]
  std::vector<std::uint32_t> colour_row_;             // [colours + 1] offsets into by_colour_
  std::vector<std::uint32_t> by_colour_;              // free points by colour, increasing in each
  std::vector<std::uint32_t> stamp_;                  // [colours] last point that saw the colour
  std::vector<Vec3> xn_, vn_, y_, fext_, prev1_, prev2_, g_;  // [points]
  std::vector<Mat3> hess_;                                    // [points]
  std::vector<Real> decrement_;          // [points] g . H^-1 g of the point's last Newton step
  std::vector<Real> bound_;              // [points] conservative bounds of this step (+inf: none)
  bool bounded_ = false;                 // some point has a bound
  std::vector<std::vector<Real>> gaps_;  // [stages][candidates] distances at take_bounds
  std::vector<Vec3> sweep_start_;        // [points] x at the sweep's take_bounds
  std::size_t transient_pools_ = 0;      // rows_ after the model pools: this step's stage pools
  // A block's Newton steps before they are taken: position, velocity, and the contacts there
  // (trial_g_, trial_h_ only receive the contact terms; touching flags say who is in contact).
  std::vector<Vec3> trial_x_, trial_v_, trial_g_;     // [points]
  std::vector<Mat3> trial_h_;                         // [points]
  std::vector<std::uint8_t> touching_, trial_touch_;  // [points]
  Real margin_ = 0;  // contact search radius beyond each link's threshold, m
  // [points] how far each point may go from x_n before the sweeps' rows are taken again, m
  std::vector<Real> allow_;
  bool compacted_ = false;                               // compact() ran this step
  std::uint64_t candidates_ = 0, candidates_swept_ = 0;  // at the last find_candidates
  Real thinnest_ = 0;   // the point contacts' thinnest region this step (PointContacts::thickness)
  DriftGuard guard_;    // the stencil stages' drift limits (re-detection, drift_guard.hpp)
  ContactEntry entry_;  // continuous detection against contacts_ from x_n (contact_entry.hpp)
  Real gravity_ = 0;
  VbdLanes lanes_;                       // the sweeps in SIMD lanes (vbd_lanes.hpp)
  std::vector<LanePoolRows> lane_rows_;  // the pools lanes_ runs
  bool arranged_ = false;                // lanes_ laid out since the last solve's sweeps
  CoarseCorrection coarse_;              // built with the static rows when settings_.coarse is on
  std::vector<Vec3> direction_;          // [points] the coarse correction's direction
};

}  // namespace maille
