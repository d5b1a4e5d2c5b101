// The simulator's health checks: non-finite forces (blamed on the stage that made them),
// non-finite positions and velocities, runaway energy, and the blow-up report.
#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>

#include "health.hpp"
#include "maille/link_loops.hpp"
#include "maille/simulator.hpp"
#include "stages.hpp"

namespace maille {

// After the force pass: one cheap pass over f. When something is not finite, the pass is
// re-run piece by piece on the same state to name the piece (a link kind, the fields or a
// plugged-in stage) that produced it, before anything is integrated.
void Simulator::check_forces(State& s) {
  if (blow_up_ || all_finite(s.f())) return;
  const std::string module = blame_forces(s);
  fail(module, "non-finite force from " + module);
}

std::string Simulator::blame_forces(State& s) {
  const Vec3* x = s.x().data();
  const Vec3* v = s.v().data();
  Vec3* f = s.f().data();
  stages::clear_forces(s);
  LinkCounters ignored;
  for (const auto& pool : model_.links.pools()) {
    accumulate_forces(*pool, x, v, f, ignored);  // outside a parallel region: serial
    if (!all_finite(s.f())) return std::string(pool->keyword());
  }
  stages::field_forces(model_, s, 1);
  if (!all_finite(s.f())) return "field_forces";
  const StageContext ctx = context(s);
  for (auto& st : stages_of(Phase::forces)) {
    st.stage->apply(model_, s, ctx);
    if (!all_finite(s.f())) return st.stage->name();
  }
  return "field_forces";
}

// Before a stage sees the state: its searches hash positions into grids, where a NaN or an
// infinity makes an index out of range. A non-finite value (written by a user between steps,
// read from a checkpoint, or an iterate of an implicit solve) is reported with the point and the
// stage it was about to reach, and no stage runs on it.
//
// Positions farther than kFarthest from the origin are refused the same way: finite, but a
// grid's cell index computed from them overflows (no scene places a point beyond 1e6 m,
// limits.hpp; only a blow-up or a value written by hand gets there).
bool Simulator::stage_input_finite(const State& s, const Stage& next) {
  constexpr Real kFarthest = Real(1e12);  // m
  if (blow_up_) return false;
  const auto x = s.x(), v = s.v();
  const Real* p = &x.data()->x;
  const std::size_t n3 = 3 * x.size();
  Real far = 0;
#pragma omp simd reduction(max : far)
  for (std::size_t i = 0; i < n3; ++i) far = std::max(far, std::abs(p[i]));
  if (far <= kFarthest && all_finite(x) && all_finite(v)) return true;
  std::size_t at = 0;
  auto sane = [&](std::size_t i) {
    return is_finite(x[i]) && is_finite(v[i]) && std::abs(x[i].x) <= kFarthest &&
           std::abs(x[i].y) <= kFarthest && std::abs(x[i].z) <= kFarthest;
  };
  while (at < x.size() && sane(at)) ++at;
  if (at == x.size()) return true;
  std::ostringstream why;
  why << (at < x.size() && is_finite(x[at]) && is_finite(v[at]) ? "position beyond 1e12 m"
                                                                : "non-finite position or velocity")
      << " at point " << at << " (" << to_string(model_.points.kind[at]) << ") before stage '"
      << next.name() << "'";
  fail(next.name(), why.str());
  return false;
}

// Every step, one pass: NaN or infinity in x or v, and twice the kinetic energy of free points
// (from the velocities the scheme holds: a cheap bound, not the exact sample). When that bound
// exceeds the runaway level, the exact energies are computed and judged; so a run that explodes
// between two samples is stopped at the step it happens.
void Simulator::check_health() {
  const auto x = state_.x();
  const auto v = state_.v();
  const Real* mass = model_.points.mass.data();
  const Real* inv_mass = model_.points.inv_mass.data();
  const auto n = static_cast<std::int64_t>(x.size());
  Real bad = 0, twice_kinetic = 0;
#pragma omp simd reduction(+ : bad, twice_kinetic)
  for (std::int64_t i = 0; i < n; ++i) {
    const Real w = inv_mass[i] > 0 ? mass[i] : Real(0);
    bad += x[i].x * 0 + x[i].y * 0 + x[i].z * 0 + v[i].x * 0 + v[i].y * 0 + v[i].z * 0;
    twice_kinetic += w * (v[i].x * v[i].x + v[i].y * v[i].y + v[i].z * v[i].z);
  }
  if (std::isfinite(bad)) {
    if (0.5 * twice_kinetic > settings_.runaway_factor * energy_scale_) check_energy();
    return;
  }
  // Name a free point first: a fixed point's row may be 0 x inf, a symptom, not the cause.
  std::size_t first = x.size(), first_free = x.size();
  for (std::size_t i = 0; i < x.size(); ++i) {
    if (is_finite(x[i]) && is_finite(v[i])) continue;
    if (first == x.size()) first = i;
    if (inv_mass[i] > 0) {
      first_free = i;
      break;
    }
  }
  const std::size_t at = first_free < x.size() ? first_free : first;
  std::ostringstream why;
  why << "non-finite position or velocity at point " << at << " ("
      << to_string(model_.points.kind[at]) << ")";
  fail("", why.str());
}

// The energy a sane run of this scene can reach: initial kinetic and elastic energy, a fall
// across the scene's extent, the wind's and the drives' kinetic energy, and 1 J/kg at least.
double Simulator::energy_scale() const {
  const auto& p = model_.points;
  constexpr Real big = std::numeric_limits<Real>::max();
  Vec3 lo{big, big, big}, hi{-big, -big, -big};
  double free_mass = 0;
  for (std::uint32_t i = 0; i < p.size(); ++i) {
    const Vec3& x = p.initial_position[i];
    lo = {std::min(lo.x, x.x), std::min(lo.y, x.y), std::min(lo.z, x.z)};
    hi = {std::max(hi.x, x.x), std::max(hi.y, x.y), std::max(hi.z, x.z)};
    if (p.inv_mass[i] > 0) free_mass += p.mass[i];
  }
  const double extent = p.size() ? norm(hi - lo) + 1.0 : 1.0;
  const double wind = norm(model_.fields.wind.velocity) * (1 + model_.fields.wind.turbulence);
  double drive = 0;
  for (const auto& d : model_.drives) drive = std::max<double>(drive, d.path.max_speed());
  const double speed2 = wind * wind + drive * drive + 1.0;
  const std::vector<Vec3> v0(p.initial_velocity.begin(), p.initial_velocity.end());
  double e0 = kinetic_energy(model_, v0);
  for (const auto& pool : model_.links.pools()) e0 += pool->energy(state_.x().data());
  // Headroom on those speeds: points flung by the wind or a drive (a flapping tip, a whipped
  // rope's end) may overtake it; twice the speed, four times the kinetic energy, is allowed for.
  constexpr double kSpeedHeadroom = 2;
  return e0 + free_mass * (norm(model_.fields.gravity) * extent +
                           0.5 * speed2 * kSpeedHeadroom * kSpeedHeadroom);
}

// The report: the module given (a link kind or a stage that produced non-finite values), or
// else the link kind whose worst link is the most broken (non-finite, or stretched furthest
// from its rest length), with the stability hint.
void Simulator::fail(std::string module, std::string detail) {
  std::ostringstream msg;
  msg << "blow-up detected at step " << state_.step << " (t = " << state_.time << " s): " << detail;
  WorstLink worst{0, {}, -1};
  std::string worst_kind;
  for (const auto& pool : model_.links.pools()) {
    if (pool->size() == 0) continue;
    if (!module.empty() && pool->keyword() != module) continue;
    const WorstLink w = pool->worst(state_.x().data(), state_.v().data());
    if (w.badness > worst.badness) {
      worst = w;
      worst_kind = std::string(pool->keyword());
    }
  }
  if (module.empty()) module = worst_kind.empty() ? "field_forces" : worst_kind;
  if (!worst_kind.empty())
    msg << "; started in " << worst_kind << " links: link #" << worst.index << " (points "
        << worst.ends.a << "-" << worst.ends.b << ") strain " << worst.badness;
  if (settings_.step > stability_.max_step)
    msg << "; the step h = " << settings_.step << " s exceeds the " << integrator_->name()
        << " stability limit " << stability_.max_step << " s set by " << stability_.link_kind
        << " links at point " << stability_.point << " (omega = " << stability_.omega
        << " rad/s): reduce the step or the stiffness";
  blow_up_ = BlowUp{state_.step, state_.time, module, msg.str()};
}

// The stages' checks of the state (Stage::inspect): a stage that asks to stop ends the run like
// a blow-up, at this step (the state of its start), naming the stage.
bool Simulator::inspect_stages(bool sampled) {
  for (Installed& st : stages_) {
    const std::string why = st.stage->inspect(model_, state_, profile_, sampled);
    if (why.empty()) continue;
    std::ostringstream msg;
    msg << "stopped at step " << state_.step << " (t = " << state_.time << " s) by stage '"
        << st.stage->name() << "': " << why;
    blow_up_ = BlowUp{state_.step, state_.time, st.stage->name(), msg.str()};
    return false;
  }
  return true;
}

}  // namespace maille
