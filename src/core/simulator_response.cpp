// Response stages under a scheme that solves for the step's velocity (ResponseTiming::after_solve,
// implicit Euler): the facet method's inverse dynamics on the motion the solve proposes.
//
// Implicit Euler ends its step with x_n+1 = x_n + h v_n+1, so the segment a point travels is
// x_n -> x_n + h v_n+1, exactly the segment a response stage tests for a scheme that drifts with
// the velocity it holds (StageContext::drift_after_kick = false). The stage is run on the state
// (x_n, v_n+1) with the step's mean force m (v_n+1 - v_n) / h, the force that produced the
// solved motion (the facets' response reads it to tell a resting contact from an impact and to
// hold a resting point by Coulomb's rule). It rewrites v_n+1 of the points that hit a facet; they
// then move to x_n + h v'. The others keep the solve's own x_n+1 and v_n+1, bit for bit.
//
// What the solve does not know: a point stopped by a facet pulls on its neighbours only from the
// next step on (their springs were solved with it going through). That is the classical
// post-solve response (Bridson et al. 2002 apply impulses after the step the same way).
#include <algorithm>

#include "health.hpp"
#include "maille/simulator.hpp"
#include "simulator_detail.hpp"

namespace maille {

void Simulator::keep_step_start() {
  if (stages_of(Phase::response).empty()) return;
  const std::size_t n = state_.size();
  if (start_x_.size() != n) {  // after a reset or an edit: sized once, then reused
    start_x_.assign(n, Vec3{});
    start_v_.assign(n, Vec3{});
    solved_x_.assign(n, Vec3{});
    solved_v_.assign(n, Vec3{});
  }
  std::copy(state_.x().begin(), state_.x().end(), start_x_.begin());
  std::copy(state_.v().begin(), state_.v().end(), start_v_.begin());
}

void Simulator::respond_to_solved_motion() {
  const auto response = stages_of(Phase::response);
  if (response.empty()) return;
  if (!stage_input_finite(state_, *response.front().stage)) return;
  const std::size_t n = state_.size();
  const Real h = static_cast<Real>(settings_.step);
  const auto x = state_.x(), v = state_.v(), f = state_.f();
  const auto& mass = model_.points.mass;
  const auto& inv_mass = model_.points.inv_mass;
  std::copy(x.begin(), x.end(), solved_x_.begin());
  std::copy(v.begin(), v.end(), solved_v_.begin());
  for (std::size_t i = 0; i < n; ++i) {
    x[i] = start_x_[i];
    f[i] = inv_mass[i] > 0 ? (v[i] - start_v_[i]) * (mass[i] / h) : Vec3{};
  }
  StageContext ctx = context(state_);
  ctx.drift_after_kick = false;  // the segment is x_n -> x_n + h v_n+1
  for (auto& st : response) {
    {
      detail::Timed t(profile_, st.profile_id);
      st.stage->apply(model_, state_, ctx);
    }
    if (!all_finite(state_.v())) {
      fail(st.stage->name(), "non-finite velocity written by stage '" + st.stage->name() + "'");
      return;
    }
  }
  for (std::size_t i = 0; i < n; ++i)
    x[i] = inv_mass[i] > 0 && !(v[i] == solved_v_[i]) ? start_x_[i] + v[i] * h : solved_x_[i];
}

}  // namespace maille
