// Vertex block descent for implicit Euler (implicit_vbd.hpp has the formulation; the contact
// rows, candidates, compaction and colouring are in vbd_contact_rows.cpp).
//
//   begin     x_n, v_n; f_ext = f - links - implicit contacts - drag, all at the step's start;
//             y = x_n + h v_n + h^2 f_ext / m
//   guess     x = x_n + h v_n + h^2 a~ (the paper's adaptive guess: the external acceleration
//             kept only as far as last step's acceleration went along it)
//   candidates  conditional links closer than threshold + margin at x_n, margin = twice the
//             guess's largest motion (found again when a point moves more than margin / 2);
//             contact links that stages found this step
//   colour    greedy colouring of the free points' graph (links, candidates, and the four
//             points of each point-triangle candidate that stages found)
//   sweeps    colour by colour: g_i, H_i, x_i += H_i^-1 g_i
//   coarse    after every second sweep (not the last): x += alpha p, p from a linear solve over
//             aggregates of points (vbd_coarse.hpp); with coarse = "off", Chebyshev acceleration
//             after each sweep instead: x = w (x - x_prev2) + x_prev2, turned off for the step
//             when a sweep's merit (sum of g_i . H_i^-1 g_i) more than doubles (the fallback)
//   thin      a point whose guess, or whose solved position, lies more than half the thinnest
//             contact region away from x_n has its segment from x_n tested at that spacing; it
//             stops just inside the first contact it meets (continuous detection: a cloth
//             thrown at a 1 cm box at 1/60 s moves 17 cm a step)
//   bounds    points of point-triangle candidates move at most 0.4 of their distances at the
//             step's start (conservative bounds: guess, Newton steps and extrapolation)
//   drift     points of a stencil stage stay within its drift limit of their predicted places
//             (drift_guard.hpp); a move held there has the stages search again before the next
//             sweep (re-detection: the pairs they had left out may have come near)
//   end       v = (x - x_n) / h
//
// Determinism: a point's g and H sum its links in a fixed order (pool by pool, slot by slot)
// and a colour's points depend only on other colours, so the result does not depend on how
// threads split a colour; the residual is a maximum, which does not depend on the order.
#include "implicit_vbd.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <functional>
#include <limits>
#include <string>

#include "implicit_system.hpp"
#include "maille/link_loops.hpp"
#include "maille/link_set.hpp"
#include "maille/shared_laws.hpp"
#include "maille/stage.hpp"

namespace maille {

namespace {
constexpr std::int64_t kBlock = 64;            // points per thread task in a colour
constexpr std::size_t kParallelPoints = 2048;  // fewer free points: one thread
// The State memory's key, made once (kVbdMemory is 18 characters: a std::string of it made per
// step would allocate).
const std::string kMemory{kVbdMemory};

}  // namespace

void VertexBlockDescent::reset() {
  points_ = 0;
  coarse_.reset();
  static_ready_ = false;
  coloured_ = false;
  rows_.clear();
  free_.clear();
}

void VertexBlockDescent::begin(const Model& m, const State& s, Real h, double t_next,
                               ForceEvaluator& forces) {
  forces_ = &forces;
  const std::size_t n = s.size();
  if (n != points_) {
    points_ = n;
    static_ready_ = false;
    for (auto* a :
         {&xn_, &vn_, &y_, &fext_, &prev1_, &prev2_, &g_, &trial_x_, &trial_v_, &trial_g_})
      a->assign(n, Vec3{});
    hess_.assign(n, Mat3{});
    decrement_.assign(n, Real(0));
    bound_.assign(n, std::numeric_limits<Real>::infinity());
    allow_.assign(n, Real(0));
    trial_h_.assign(n, Mat3{});
    touching_.assign(n, 0);
    trial_touch_.assign(n, 0);
  }
  if (!static_ready_) build_static_rows(m);
  // This step's transient pools (stages' contacts) after the model's pools.
  const std::size_t model_pools = m.links.pools().size();
  const ContactSet& set = forces.contacts();
  const auto transient = set.pairs();
  rows_.resize(model_pools + transient.size());
  for (std::size_t p = 0; p < transient.size(); ++p) {
    rows_[model_pools + p].pool = transient[p];
    rows_[model_pools + p].fixed = false;
  }
  triangle_rows(set.stencils());
  triangle_contacts_.assign(set.stencils().begin(), set.stencils().end());
  transient_pools_ = transient.size();
  bounded_ = triangle_stages_ > 0 || transient_pools_ > 0;
  take_bounds(m, s.x().data());
  dynamic_ = model_dynamic_ || !transient.empty() || triangle_stages_ > 0;
  const auto pc = set.obstacles();
  contacts_.assign(pc.begin(), pc.end());
  entry_.begin(pc, xn_.data(), n);
  margin_ = -1;  // no candidates yet this step
  compacted_ = false;

  const Vec3* x = s.x().data();
  const Vec3* v = s.v().data();
  guard_.first_search(set.stencils(), m, x, v, h);
  std::copy(x, x + n, xn_.begin());
  std::copy(v, v + n, vn_.begin());
  // f_ext: the evaluated forces without the model's links, which the solve takes implicitly
  // (the contact set's forces are not in s.f(): the solve evaluates them itself).
  std::fill(g_.begin(), g_.end(), Vec3{});
  LinkCounters counters;
  for (std::size_t p = 0; p < model_pools; ++p)
    accumulate_forces(*rows_[p].pool, x, v, g_.data(), counters);
  thinnest_ = std::numeric_limits<Real>::infinity();
  for (PointContacts* c : contacts_) {  // friction's normal force held from (x_n, t_n)
    thinnest_ = std::min(thinnest_, c->thickness());
    c->set_time(s.time);
    c->lag(free_, x, v, t_next);
  }
  const auto f = s.f();
  const Real drag = m.fields.air_drag;
  for (std::size_t i = 0; i < n; ++i) {
    fext_[i] = f[i] - g_[i];
    if (m.points.inv_mass[i] > 0) {
      fext_[i] += v[i] * (drag * m.points.mass[i]);
      y_[i] = x[i] + v[i] * h + fext_[i] * (h * h * m.points.inv_mass[i]);
    } else {
      y_[i] = x[i];
    }
  }
  gravity_ = norm(m.fields.gravity);
}

// g_i = m_i/h^2 (y_i - x_i) - gamma m_i v_i + links + contacts; H_i likewise. With
// `skip_kept`, the pools the coarse correction keeps are left out (coarse_terms adds them).
void VertexBlockDescent::point_terms(std::span<const std::uint32_t> points, const Model& m,
                                     const Vec3* x, const Vec3* v, Real h, bool skip_kept) {
  inertia_terms(points, m, x, v, h);
  later_terms(points, x, v, h, 0, skip_kept);
}

// The terms of inertia and drag: g_i and H_i from zero (the lanes compute the same ones,
// vbd_lanes_kernel.hpp).
void VertexBlockDescent::inertia_terms(std::span<const std::uint32_t> points, const Model& m,
                                       const Vec3* x, const Vec3* v, Real h) {
  const Real inv_h = Real(1) / h, inv_h2 = inv_h * inv_h;
  const Real drag = m.fields.air_drag;
  for (const std::uint32_t i : points) {
    const Real mass = m.points.mass[i];
    g_[i] = (y_[i] - x[i]) * (mass * inv_h2) - v[i] * (drag * mass);
    hess_[i] = Mat3::identity() * (mass * (inv_h2 + drag * inv_h));
    touching_[i] = 0;
  }
}

// The links of rows_[first_pool] on, then the stages' contacts, added to g_i and H_i in the
// order that makes a point's sums the same whichever path computed the earlier terms.
void VertexBlockDescent::later_terms(std::span<const std::uint32_t> points, const Vec3* x,
                                     const Vec3* v, Real h, std::size_t first_pool,
                                     bool skip_kept) {
  const Real inv_h = Real(1) / h;
  for (std::size_t p = first_pool; p < rows_.size(); ++p) {
    const PoolRows& r = rows_[p];
    if (skip_kept && coarse_.blocks_of(r.pool)) continue;
    const bool swept = !r.fixed;  // the compacted rows (compact()); fixed pools all act
    add_point_terms(*r.pool, points, (swept ? r.swept_row : r.row).data(),
                    (swept ? r.swept_slots : r.slots).data(), x, v, inv_h, g_.data(), hess_.data());
  }
  for (std::size_t t = 0; t < triangle_stages_; ++t) {
    const TriangleRows& r = triangles_[t];
    r.contacts->add_point_terms(points, r.swept_row.data(), r.swept_entries.data(), x, v, inv_h,
                                g_.data(), hess_.data());
  }
  for (const PointContacts* c : contacts_)
    c->add_terms(points, x, v, inv_h, g_.data(), hess_.data(), touching_.data());
}

// Lays the lanes out for the colours just found: the leading model pools that run in lanes
// (vbd_lanes.hpp; a later pool in lanes would add its sums before an earlier scalar one's).
void VertexBlockDescent::arrange_lanes() {
  std::vector<LanePoolRows>& pools = lane_rows_;
  pools.clear();
  if (vbd_lane_width() > 1)
    for (const PoolRows& r : rows_) {
      if (!r.fixed || !VbdLanes::runs(*r.pool)) break;
      pools.push_back({r.pool, r.row.data(), r.slots.data()});
    }
  lanes_.arrange(pools, colour_row_, by_colour_);
  arranged_ = true;
}

// One Gauss-Seidel sweep, colour by colour; returns the sweep's merit, the sum over free points
// (in index order: the same on any threads) of g_i . H_i^-1 g_i, each taken just before the
// point's own update. For a quadratic G it is the energy norm of the block-preconditioned
// gradient: twice the decrease the sweep's Newton steps expect, so a sweep that raises it has
// moved away from the minimum (the fallback's test). The largest |g_i| was tried first: one
// point's imbalance jumps at every contact that starts, and it turned the acceleration off in
// most steps (docs/implicit.md).
//
// A contact's force (its damper above all) jumps where the contact starts, so a Newton step
// that enters a contact from outside can land deep inside, past the jump, and the next one
// come back out: a point would bounce between deep inside and just outside. A step that starts
// a contact therefore stops just inside the surface (the next Newton step, with the contact's
// stiffness, goes on from there). A step that leaves a contact is taken whole when it is
// shorter than half the thinnest contact region (it cannot have crossed that region to leave
// by its far side): stopping every leaving step at the surface held each touching point where
// it touched (on a convex obstacle any sliding step leaves it), which glued a cloth to a
// sphere and stretched it 40 % at 1/60 s. Longer leaving steps stop just inside.
Real VertexBlockDescent::sweep(const Model& m, Vec3* x, Vec3* v, Real h) {
  const std::size_t colours = colour_row_.size() - 1;
  if (bounded_) {  // the bounds, and the sweep's start for the stages to skip far candidates
    take_bounds(m, x);
    sweep_start_.assign(x, x + points_);
    for (std::size_t t = 0; t < triangle_stages_; ++t)
      triangles_[t].contacts->set_sweep_start(sweep_start_.data(), gaps_[t].data());
  }
  const bool parallel = threads_ > 1 && free_.size() >= kParallelPoints;
#pragma omp parallel num_threads(threads_) if (parallel)
  for (std::size_t c = 0; c < colours; ++c) {
    const std::int64_t begin = colour_row_[c], end = colour_row_[c + 1];
    const std::int64_t blocks = (end - begin + kBlock - 1) / kBlock;
#pragma omp for schedule(static)
    for (std::int64_t b = 0; b < blocks; ++b) {
      const std::int64_t lo = begin + b * kBlock, hi = std::min(end, lo + kBlock);
      update_block(std::uint32_t(c), std::uint32_t(lo - begin), std::uint32_t(hi - lo), m, x, v, h);
    }
  }
  for (std::size_t t = 0; t < triangle_stages_ && bounded_; ++t)
    triangles_[t].contacts->set_sweep_start(nullptr, nullptr);
  Real merit = 0;
  for (const std::uint32_t i : free_) merit += decrement_[i];
  return merit;
}

// The Newton steps of `count` points of a colour from by_colour_[colour_row_[c] + offset], in
// lanes when they run (the same bits: vbd_lanes.hpp), then their contacts.
void VertexBlockDescent::update_block(std::uint32_t colour, std::uint32_t offset,
                                      std::uint32_t count, const Model& m, Vec3* x, Vec3* v,
                                      Real h) {
  const std::span<const std::uint32_t> pts(by_colour_.data() + colour_row_[colour] + offset, count);
  const Real inv_h = Real(1) / h, half_thinnest = Real(0.5) * thinnest_;
  if (lanes_.width() > 1) {
    for (const std::uint32_t i : pts) touching_[i] = 0;
    const vbd_lanes::Step step{&x[0].x, &v[0].x,       &y_[0].x,         m.points.mass.data(),
                               inv_h,   inv_h * inv_h, m.fields.air_drag};
    lanes_.terms(colour, offset, count, step, &g_[0].x, &hess_[0].m[0][0]);
    later_terms(pts, x, v, h, lanes_.pools(), false);
    alignas(64) Real dx[3 * kBlock];
    lanes_.solve(colour, offset, count, &g_[0].x, &hess_[0].m[0][0], dx);
    for (std::uint32_t k = 0; k < count; ++k)
      newton_step(pts[k], x, {dx[3 * k], dx[3 * k + 1], dx[3 * k + 2]}, inv_h);
  } else {
    point_terms(pts, m, x, v, h);
    for (const std::uint32_t i : pts) newton_step(i, x, inverse_spd(hess_[i]) * g_[i], inv_h);
  }
  for (const PointContacts* c : contacts_)
    c->add_terms(pts, trial_x_.data(), trial_v_.data(), inv_h, trial_g_.data(), trial_h_.data(),
                 trial_touch_.data());
  for (const std::uint32_t i : pts) {
    // Same contacts; or leaving one by less than half the thinnest contact region (a longer
    // step could leave a thin box through its far side).
    if (trial_touch_[i] == touching_[i] ||
        (touching_[i] && leaves_cleanly(i, x[i], half_thinnest))) {
      x[i] = trial_x_[i];
      v[i] = trial_v_[i];
      continue;
    }
    // Starting or (far) leaving a contact: the step stops just inside the surface (bisection
    // on whether the point touches), touching; the next step sees the contact's stiffness.
    const Vec3 x0 = x[i], dx = trial_x_[i] - x0;
    const auto [lo, hi] = contact_change(i, x0, dx, inv_h);
    x[i] = x0 + dx * (touching_[i] ? lo : hi);
    v[i] = (x[i] - xn_[i]) * inv_h;
    touching_[i] = 1;  // just inside either way: the acceleration leaves it there
  }
}

// Point i's trial of its Newton step dx (a non-finite one is left to the health check).
void VertexBlockDescent::newton_step(std::uint32_t i, const Vec3* x, const Vec3& dx, Real inv_h) {
  trial_x_[i] = is_finite(dx) ? x[i] + dx : x[i];
  if (bounded_) trial_x_[i] = within_bound(x[i], trial_x_[i], bound_[i]);
  // Within its drift limit; a point touching an obstacle goes where the obstacle's rules send it
  // (held there, a point pressed into a sphere by the cloth above it came out a ball's limit a
  // sweep at most: 3 cm deep at 1/20 s), and only has the stages search again after the sweep.
  if (guard_.active()) {
    if (touching_[i])
      guard_.note(i, trial_x_[i]);
    else
      trial_x_[i] = guard_.hold(i, x[i], trial_x_[i]);
  }
  trial_v_[i] = (trial_x_[i] - xn_[i]) * inv_h;
  trial_touch_[i] = 0;
  trial_g_[i] = Vec3{};
  trial_h_[i] = Mat3{};
  decrement_[i] = is_finite(dx) ? dot(g_[i], dx) : Real(0);
}

// Where on the move x0 -> x0 + dx point i's contact state (touching or not, as touching_[i]
// says at x0) changes: [lo, hi] within 1/1024 of the move, lo on the side of x0. Uses the
// trial arrays of point i only.
std::pair<Real, Real> VertexBlockDescent::contact_change(std::uint32_t i, const Vec3& x0,
                                                         const Vec3& dx, Real inv_h) {
  Real lo = 0, hi = 1;
  for (int k = 0; k < kVbdBisections; ++k) {
    const Real mid = Real(0.5) * (lo + hi);
    (touches_at(i, x0 + dx * mid, inv_h) == bool(touching_[i]) ? lo : hi) = mid;
  }
  return {lo, hi};
}

// The one-point probe of the point contacts: whether point i touches one at `at` (moving from
// x_n in the step). Uses the trial arrays of point i only (their g and H receive the terms).
bool VertexBlockDescent::touches_at(std::uint32_t i, const Vec3& at, Real inv_h) {
  const std::span<const std::uint32_t> one(&i, 1);
  trial_x_[i] = at;
  trial_v_[i] = (at - xn_[i]) * inv_h;
  trial_touch_[i] = 0;
  for (const PointContacts* c : contacts_)
    c->add_terms(one, trial_x_.data(), trial_v_.data(), inv_h, trial_g_.data(), trial_h_.data(),
                 trial_touch_.data());
  return trial_touch_[i] != 0;
}

void VertexBlockDescent::initial_guess(const Model& m, State& s, Real h) {
  std::vector<double>& last = s.memory(kMemory);  // v at the last step's start
  const bool history = last.size() == 3 * points_;
  Vec3* x = s.x().data();
  Vec3* v = s.v().data();
  for (const std::uint32_t i : free_) {
    const Vec3 a_ext = fext_[i] * m.points.inv_mass[i];
    Vec3 a = a_ext;
    if (history) {
      const Vec3 v_last{last[3 * i], last[3 * i + 1], last[3 * i + 2]};
      const Vec3 a_last = (vn_[i] - v_last) * (Real(1) / h);
      const Real len = norm(a_ext);
      // The paper's clamp: along a_ext, last step's acceleration within [0, |a_ext|] (a point
      // at rest on a support keeps none of it). Its part across a_ext (a cloth sliding down a
      // slope) was tried and dropped: on cloth_on_sphere it replayed impacts (docs/implicit.md).
      a = len > 0 ? a_ext * (std::clamp(dot(a_last, a_ext) / len, Real(0), len) / len) : Vec3{};
    }
    x[i] = xn_[i] + vn_[i] * h + a * (h * h);
    if (bounded_) x[i] = within_bound(xn_[i], x[i], bound_[i]);
    v[i] = (x[i] - xn_[i]) * (Real(1) / h);
  }
  last.resize(3 * points_);
  for (std::size_t i = 0; i < points_; ++i) {
    last[3 * i] = vn_[i].x;
    last[3 * i + 1] = vn_[i].y;
    last[3 * i + 2] = vn_[i].z;
  }
}

VbdResult VertexBlockDescent::solve(const Model& m, State& s, Real h) {
  VbdResult result;
  initial_guess(m, s, h);
  Vec3* x = s.x().data();
  Vec3* v = s.v().data();
  entry_.stop_at_first_touch(free_, x, v, h,
                             false);  // the guess: the solve starts at the first contact
  if (guard_.active()) {              // the guess is one straight move from x_n, held on it
    guard_.take_common(x);
    for (const std::uint32_t i : free_) {
      const Vec3 held = guard_.hold(i, xn_[i], x[i]);
      if (held == x[i]) continue;
      x[i] = held;
      v[i] = (x[i] - xn_[i]) * (Real(1) / h);
    }
  }
  if (guard_.active() && guard_.search_due() && search_again(m, s)) {
    // found again where the guess was held: candidates, colours and compaction done there
  } else if (dynamic_) {
    find_candidates(m, xn_.data(), margin_for(x));
    colour();
    compact(x);
  } else if (!coloured_) {
    colour();
    coloured_ = true;
  }
  result.colours = int(colour_row_.size()) - 1;
  // The lanes: laid out again for a width set since (tests, benchmarks), else the parameters
  // refreshed (they may be edited between steps).
  if (!lanes_.current())
    arrange_lanes();
  else if (!arranged_)
    lanes_.refresh_params();
  arranged_ = false;  // the next solve refreshes

  const Real half_thinnest = Real(0.5) * thinnest_;
  const bool coarse = coarse_.aggregates() > 0;
  // The coarse correction replaces the acceleration: with both, the 64^2 cloth on a sphere
  // stretched 27 % at 1/60 s instead of 6 % (docs/implicit.md).
  const Real rho = coarse ? Real(0) : settings_.acceleration;
  bool accelerate = rho > 0;
  Real omega = 1, last_merit = std::numeric_limits<Real>::infinity();
  if (accelerate)
    for (const std::uint32_t i : free_) prev1_[i] = x[i];  // x^(0): the k = 2 update needs it
  for (int k = 1; k <= settings_.iterations; ++k) {
    if (k > 1 && forces_ && forces_->stop_requested()) {
      result.stopped = true;  // the simulator puts the step's start back
      return result;
    }
    const Real merit = sweep(m, x, v, h);
    ++result.sweeps;
    if (accelerate && k >= 3 && merit > kFallbackGrowth * last_merit) {
      accelerate = false;  // the extrapolation overshot: plain sweeps from here
      ++result.acceleration_resets;
    }
    last_merit = merit;
    if (accelerate) extrapolate(k, rho, omega, x, v, h, half_thinnest);
    // A coarse correction after every kCoarseEvery-th sweep, never after the last (the sweeps
    // smooth what the correction leaves between aggregates).
    if (coarse && k % kCoarseEvery == 0 && k < settings_.iterations && coarse_step(m, x, v, h))
      ++result.coarse_corrections;
    // A point held at its drift limit: the stages search again before the next sweep.
    if (guard_.active() && k < settings_.iterations && guard_.search_due() && search_again(m, s)) {
      // candidates, colours and compaction taken at the new search
    } else if (dynamic_ && k < settings_.iterations && 2 * largest_motion(x) > margin_) {
      // Contacts found for a smaller motion: find them again (and colour again) first.
      find_candidates(m, xn_.data(), margin_for(x));
      colour();
      compact(x);
      ++result.candidate_refreshes;
    } else if (dynamic_ && k < settings_.iterations && beyond_allowance(x)) {
      compact(x);  // the same candidates and colours, the sweeps' share taken again
    }
  }
  entry_.stop_at_first_touch(free_, x, v, h, true);  // the solve's result: only if it went through
  result.candidates = candidates_;
  result.candidates_swept = candidates_swept_;
  result.searches_again = guard_.searches_again();
  return result;
}

// The stages' search again at the iterate (x, and v = (x - x_n) / h, as the sweeps leave them):
// their arrays refilled in place, or added to around the held points when they are few
// (DriftGuard::moved), so the set's views stand; the rows, colours and compaction follow. False
// when no stage searched (the guard then stays as it was).
bool VertexBlockDescent::search_again(const Model& m, State& s) {
  const std::span<const std::uint32_t> moved = guard_.moved(s.x().data());  // empty: everywhere
  if (!forces_ || !forces_->find_contacts_again(s, moved)) return false;
  const Vec3* x = s.x().data();
  const ContactSet& set = forces_->contacts();
  triangle_rows(set.stencils());
  if (moved.empty())
    guard_.searched_again(x);
  else
    guard_.searched_near(x);
  find_candidates(m, xn_.data(), margin_for(x));
  colour();
  compact(x);
  return true;
}

// Chebyshev's extrapolation after sweep k: x = omega (x - x^(k-2)) + x^(k-2).
void VertexBlockDescent::extrapolate(int k, Real rho, Real& omega, Vec3* x, Vec3* v, Real h,
                                     Real half_thinnest) {
  omega = law::chebyshev_omega(k, rho, omega);
  // Points in contact (or that entered one in this sweep) are not extrapolated: across a stiff
  // contact's jump the extrapolation throws a point deep into (or through) a thin obstacle.
  if (k >= 2)
    for (const std::uint32_t i : free_) {
      // Nor points near a face (a bound), nor by more than half the thinnest contact region (the
      // sweeps' own steps are watched in update_block), nor past the drift limit.
      const Vec3 to = law::chebyshev_place(x[i], prev2_[i], omega);
      const bool bounded = bound_[i] < std::numeric_limits<Real>::infinity();
      if (!law::chebyshev_takes(touching_[i] != 0, bounded, to - x[i], half_thinnest) ||
          !guard_.inside(i, to))
        continue;
      x[i] = to;
      v[i] = (x[i] - xn_[i]) * (Real(1) / h);
    }
  std::swap(prev1_, prev2_);
  for (const std::uint32_t i : free_) prev1_[i] = x[i];
}

// g and H of every free point at (x, v) for the coarse correction, and the blocks of the links
// it keeps: its always-active pools link by link (one evaluation per link, where a point's
// gather makes two: the correction's gradient pass cost about a sweep), the rest point by point
// in blocks (threads when there are many points). The link pass scatters its sums in storage
// order on one thread, so the result does not depend on the threads.
void VertexBlockDescent::coarse_terms(const Model& m, const Vec3* x, const Vec3* v, Real h) {
  const bool parallel = threads_ > 1 && free_.size() >= kParallelPoints;
  const auto count = static_cast<std::int64_t>(free_.size());
  const std::int64_t blocks = (count + kBlock - 1) / kBlock;
#pragma omp parallel for schedule(static) num_threads(threads_) if (parallel)
  for (std::int64_t b = 0; b < blocks; ++b) {
    const std::int64_t lo = b * kBlock, hi = std::min(count, lo + kBlock);
    point_terms({free_.data() + lo, std::size_t(hi - lo)}, m, x, v, h, true);
  }
  // The pass adds into fixed points too: from zero, so that nothing grows step after step.
  for (std::size_t i = 0; i < points_; ++i)
    if (!(m.points.inv_mass[i] > 0)) {
      g_[i] = Vec3{};
      hess_[i] = Mat3{};
    }
  for (const PoolRows& r : rows_)
    if (Mat3* kept = coarse_.blocks_of(r.pool))
      add_link_terms(*r.pool, x, v, Real(1) / h, g_.data(), hess_.data(), kept);
}

// One coarse correction (vbd_coarse.hpp): x += alpha p, the coarse matrix factorised at x (once
// per correction: the contacts a sweep starts change the diagonal, and a matrix kept from the
// step's first correction stretched the 64^2 cloth on a sphere 124 % at 1/60 s instead of 6 %).
// Contacts hold as in a sweep. Points of two-body contacts (those with conservative bounds) are
// left to the sweeps: the coarse matrix holds a contact pair's blocks on the diagonal only, as if
// each point were anchored to the world, and moved by it a cloth lying on a cloth tilted 60
// degrees without friction did not slide (leapfrog: 2.55 m in 1 s). A touching point does not
// move into its obstacle, nor farther than half the thinnest contact region from x_n; one that
// would enter a point contact stops just inside it. A point whose move would be longer than half
// the thinnest contact region stays (a thin box). False when no correction was taken (the coarse
// matrix not positive definite, or a zero direction).
bool VertexBlockDescent::coarse_step(const Model& m, Vec3* x, Vec3* v, Real h) {
  coarse_terms(m, x, v, h);
  if (!coarse_.prepare(hess_.data())) return false;
  const Real alpha = coarse_.direction(g_.data(), direction_.data());
  if (!(alpha > 0)) return false;
  const Real inv_h = Real(1) / h, half_thinnest = Real(0.5) * thinnest_;
  if (bounded_) take_bounds(m, x);
  for (const std::uint32_t i : free_) {
    if (bound_[i] < std::numeric_limits<Real>::infinity()) continue;  // in a two-body contact
    Vec3 d = direction_[i] * alpha;
    if (touching_[i]) {
      for (const PointContacts* c : contacts_) {  // not into an obstacle
        const Vec3 push = c->push(i, x[i]);
        const Real into = dot(push, d);
        if (into < 0) d -= push * (into / norm2(push));
      }
      // Nor, in contact, farther from x_n than half the thinnest contact region (inside a thin
      // box the push may point to a side face: leaves_cleanly).
      if (norm2(x[i] + d - xn_[i]) > half_thinnest * half_thinnest) continue;
    }
    const Vec3 to = x[i] + d;
    if (!is_finite(d) || norm2(d) > half_thinnest * half_thinnest) continue;
    if (!guard_.inside(i, to)) continue;  // past its drift limit: left to the sweeps
    if (!contacts_.empty()) {
      if (touches_at(i, to, inv_h) && !touching_[i]) {
        x[i] += d * contact_change(i, x[i], d, inv_h).second;
        v[i] = (x[i] - xn_[i]) * inv_h;
        touching_[i] = 1;
        continue;
      }
    }
    x[i] = to;
    v[i] = (x[i] - xn_[i]) * inv_h;
  }
  return true;
}

// Whether point i, touching a contact at x[i], may take its Newton step trial_x_[i] out of it
// whole: a step that does not move against any contact's push at x[i] (PointContacts::push:
// sliding off a convex obstacle leaves it; a point pressed through a thin box, or between a
// conditional obstacle's samples, moves against it), and whose segment from x_n is shorter than
// half the thinnest contact region. The second test is not redundant: inside a thin box
// mapped canonically the push may point to a side face, so a point pressed down through it
// does not move against it; first_touch on the segment was tried and let such a point through
// (it touched at x_n already). A longer leaving step stops just inside, as entering ones do.
bool VertexBlockDescent::leaves_cleanly(std::uint32_t i, const Vec3& from, Real half_thinnest) {
  const Vec3 to = trial_x_[i], dx = to - from;
  for (const PointContacts* c : contacts_)
    if (dot(c->push(i, from), dx) < 0) return false;
  return norm2(to - xn_[i]) <= half_thinnest * half_thinnest;
}

double VertexBlockDescent::residual(const Model& m, const State& s, Real h) {
  const Vec3* x = s.x().data();
  const Vec3* v = s.v().data();
  if (dynamic_ && 2 * largest_motion(x) > margin_) {
    find_candidates(m, xn_.data(), margin_for(x));
    compact(x);
  } else if (dynamic_ && (!compacted_ || beyond_allowance(x))) {
    compact(x);
  }
  Real worst = 0, heaviest = 0;
  const bool parallel = threads_ > 1 && free_.size() >= kParallelPoints;
  const auto count = static_cast<std::int64_t>(free_.size());
  const std::int64_t blocks = (count + kBlock - 1) / kBlock;
#pragma omp parallel for schedule(static) num_threads(threads_) if (parallel) \
    reduction(max                                                             \
              : worst, heaviest)
  for (std::int64_t b = 0; b < blocks; ++b) {
    const std::int64_t lo = b * kBlock, hi = std::min(count, lo + kBlock);
    const std::span<const std::uint32_t> pts(free_.data() + lo, std::size_t(hi - lo));
    point_terms(pts, m, x, v, h);
    for (const std::uint32_t i : pts) {
      worst = std::max(worst, norm(g_[i]));
      heaviest = std::max(heaviest, m.points.mass[i]);
    }
  }
  const Real g = gravity_ > 0 ? gravity_ : Real(9.81);
  return heaviest > 0 ? double(worst / (heaviest * g)) : 0.0;
}

}  // namespace maille
