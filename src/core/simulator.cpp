#include "maille/simulator.hpp"

#ifdef _OPENMP
#include <omp.h>
#endif

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <sstream>
#include <stdexcept>

#include "follow_cores.hpp"
#include "free_cores.hpp"
#include "health.hpp"
#include "maille/motion_bound.hpp"
#include "maille/stage_keys.hpp"
#include "maille/threads.hpp"
#include "simulator_detail.hpp"
#include "stages.hpp"
#include "wind_rows.hpp"

namespace maille {

using detail::Timed;

namespace {

// Below this many points a step is a few microseconds and threads cost more than they give.
constexpr std::uint32_t kParallelThreshold = 4096;

}  // namespace

Simulator::Simulator(Model model, SimulationSettings settings)
    : model_(std::move(model)), settings_(std::move(settings)), ids_(std::make_unique<StageIds>()) {
  if (!(settings_.step > 0)) throw std::invalid_argument("step must be > 0");
  if (settings_.publish_every < 1) throw std::invalid_argument("publish_every must be >= 1");
  if (settings_.sample_every < 0) throw std::invalid_argument("sample_every must be >= 0");
  if (settings_.sample_every == 0) settings_.sample_every = settings_.publish_every;

  if (const std::string why = check_model(model_); !why.empty())
    throw std::invalid_argument("model: " + why);
  const std::uint32_t n = model_.points.size();
#ifdef _OPENMP
  const int cores = omp_get_num_procs();
#else
  const int cores = 1;
#endif
  // The default: to start with, one thread for small scenes, else the cores free now
  // (free_cores.hpp); then the free cores and the faster count among 1 and them, measured
  // during the run (simulator_threads.cpp): a thread that shares its core with another program
  // makes every barrier wait for it, and small scenes can be costly.
  cores_ = cores;
  follows_cores_ = settings_.threads == 0 && cores > 1 && settings_.backend == "cpu";
  free_at_start_ = follows_cores_ ? detail::free_cores(cores) : 1;
  threads_ = usable_threads(settings_.threads > 0     ? settings_.threads
                            : n >= kParallelThreshold ? free_at_start_
                                                      : 1);
  // libgomp exits the process when it cannot start a thread it is asked for: ask first.
  if (const std::string why = threads_startable(threads_); !why.empty())
    throw std::invalid_argument(why);
  note_teams(follows_cores_ ? cores_ : threads_);
  model_.prepare();
  build_integrator(settings_.integrator);

  auto& ids = *ids_;
  ids.drive = profile_.stage("drive");
  ids.clear = profile_.stage("clear_forces");
  ids.links = profile_.stage("link_forces");
  ids.fields = profile_.stage("field_forces");
  ids.integrate = profile_.stage("integrate");
  ids.after = profile_.stage("after_integration");
  ids.health = profile_.stage("health");
  ids.publish = profile_.stage("publish");
  ids.active_links = profile_.counter("active_conditional_links");
  ids.wind_faces = profile_.counter("wind_faces");
  install_model_stages();
  reset();
  if (settings_.backend != "cpu") make_backend();
}

Simulator::~Simulator() = default;

// A scheme from the registry, checked against the model and the installed stages; the
// simulator's own scheme is replaced only when every check passes.
void Simulator::build_integrator(const std::string& name) {
  const auto* entry = IntegratorRegistry::builtin().find(name);
  if (!entry)
    throw std::invalid_argument("unknown integrator '" + name +
                                "' (known: " + IntegratorRegistry::builtin().names() + ")");
  std::unique_ptr<Integrator> scheme = entry->make(settings_.implicit);
  scheme->set_threads(threads_);
  if (const std::string why = scheme->check(model_); !why.empty()) throw std::invalid_argument(why);
  if (backend_) check_backend(*scheme);
  for (const Installed& st : stages_)
    if (const std::string why = scheme->check_stage(*st.stage); !why.empty())
      throw std::invalid_argument(why);
  const auto response = stages_of(Phase::response);
  if (scheme->response_timing() == ResponseTiming::refused && !response.empty())
    throw std::invalid_argument("stage '" + response.front().stage->name() +
                                "' rewrites forces and velocities after the fact; " + name +
                                " cannot be combined with it (use leapfrog, symplectic_euler, "
                                "explicit_euler or implicit_euler)");
  integrator_ = std::move(scheme);
  settings_.integrator = name;
  restimate_stability();
}

void Simulator::restimate_stability() {
  stability_ = estimate_stability(model_, *integrator_, installed_stages());
}

void Simulator::reset() {
  const std::uint32_t n = model_.points.size();
  state_ = State(n);
  std::copy(model_.points.initial_position.begin(), model_.points.initial_position.end(),
            state_.x().begin());
  std::copy(model_.points.initial_velocity.begin(), model_.points.initial_velocity.end(),
            state_.v().begin());
  stages::drive(model_, state_, 0);
  integrator_->reset();
  for (Installed& st : stages_) st.stage->model_changed(model_);
  blow_up_.reset();
  unconverged_.reset();
  streak_ = Unconverged{};
  pending_sample_.reset();
  snapshot_ = Snapshot{};
  scratch_velocity_.assign(n, Vec3{});
  energy_scale_ = energy_scale();
  host_ahead_ = true;
  device_ahead_ = false;
}

void Simulator::on_publish(SnapshotListener listener) {
  publish_listeners_.push_back(std::move(listener));
}

void Simulator::on_sample(std::function<void(const EnergySample&, const Profile&)> listener) {
  sample_listeners_.push_back(std::move(listener));
}

void Simulator::set_step(double h) {
  if (!(h > 0)) throw std::invalid_argument("step must be > 0");
  settings_.step = h;  // leapfrog re-centres by itself: its kick spans (h_old + h_new) / 2
  restimate_stability();
}

// The old scheme's velocities are synchronised to the time of x (its forces at x first), and
// the new scheme starts from a synchronous state, as at t = 0.
void Simulator::set_integrator(const std::string& name) {
  if (name == integrator_->name()) return;
  sync_host();
  std::unique_ptr<Integrator> old = std::move(integrator_);
  const std::string old_name = settings_.integrator;
  try {
    build_integrator(name);
  } catch (...) {
    integrator_ = std::move(old);
    settings_.integrator = old_name;
    throw;
  }
  evaluate(state_);
  old->synchronized_velocity(model_, state_, static_cast<Real>(settings_.step), scratch_velocity_);
  std::copy(scratch_velocity_.begin(), scratch_velocity_.end(), state_.v().begin());
  state_.history = SchemeHistory{};
  host_ahead_ = true;
}

void Simulator::set_implicit(const ImplicitSettings& implicit) {
  const ImplicitSettings old = settings_.implicit;
  settings_.implicit = implicit;
  if (settings_.integrator != kImplicitEuler) return;  // taken when the scheme is chosen
  std::unique_ptr<Integrator> previous = std::move(integrator_);
  try {
    build_integrator(std::string(kImplicitEuler));
  } catch (...) {
    integrator_ = std::move(previous);
    settings_.implicit = old;
    throw;
  }
}

void Simulator::restore(State state, std::uint64_t frames_published) {
  if (state.size() != model_.points.size())
    throw std::invalid_argument("the state has " + std::to_string(state.size()) +
                                " points, the model " + std::to_string(model_.points.size()));
  state_ = std::move(state);
  blow_up_.reset();
  pending_sample_.reset();
  snapshot_.frame = frames_published;
  host_ahead_ = true;
  device_ahead_ = false;
}

// The step, as a table of contents. Energies are sampled between the force pass and the
// integration, when forces and (synchronised) velocities belong to the same time t_n.
// Explicit schemes: the force stages that bound each point's motion in a step (motion_bound.hpp:
// self-collision's displacement bounds) clamp the scheme's move, before the step ends.
namespace {
template <class Stages>
void bound_motions(Stages stages, const Model& m, State& s, Real h, Profile& profile) {
  for (auto& st : stages)
    if (auto* bounded = dynamic_cast<MotionBound*>(st.stage.get()))
      bounded->bound_motion(m, s, h, profile);
}
}  // namespace

bool Simulator::step() {
  interrupted_ = false;
  if (blow_up_) return false;
  if (threads_ > 1 || follows_cores_) keep_to_usable_threads();
  if (follows_cores_) follow_cores();
  profile_.set_timing(stage_timing_ == StageTiming::every_step ||
                      state_.step % static_cast<std::uint64_t>(settings_.sample_every) == 0);
  if (backend_) return step_on_backend();
  keep_for_stop();
  profile_.begin_step();
  if (!inspect_stages(state_.step % static_cast<std::uint64_t>(settings_.sample_every) == 0))
    return false;
  const auto& ids = *ids_;
  const Real h = static_cast<Real>(settings_.step);
  if (fused_grid_step(h)) {  // grid cloth alone: forces and update in one pass
    if (blow_up_) return false;
  } else {
    evaluate(state_);
    check_forces(state_);
    if (blow_up_) return false;
    const ResponseTiming responses = integrator_->response_timing();
    if (responses == ResponseTiming::before_integration) respond();
    if (blow_up_) return false;
    if (state_.step % static_cast<std::uint64_t>(settings_.sample_every) == 0) sample_energies();
    if (blow_up_) return false;
    if (responses == ResponseTiming::after_solve) keep_step_start();
    if (!advance_or_stop(h)) return false;
    if (blow_up_) return false;  // a stage refused the solver's iterate (stage_input_finite)
    if (!integrator_->uses_jacobians())
      bound_motions(stages_of(Phase::forces), model_, state_, h, profile_);
    if (responses == ResponseTiming::after_solve) respond_to_solved_motion();
    if (blow_up_) return false;
  }
  state_.time += settings_.step;
  state_.step += 1;
  {
    Timed t(profile_, ids.after);
    stages::drive(model_, state_, state_.time);
  }
  const auto after = stages_of(Phase::after_integration);
  if (const Stage* checked = first_checked(after))
    if (!stage_input_finite(state_, *checked)) return false;
  const StageContext ctx = context(state_);
  for (auto& st : after) {
    Timed t(profile_, st.profile_id);
    st.stage->apply(model_, state_, ctx);
  }
  if (health_every_ == 1 || state_.step % static_cast<std::uint64_t>(health_every_) == 0) {
    Timed t(profile_, ids.health);
    check_health();
  }
  if (blow_up_) return false;
  if (state_.step % static_cast<std::uint64_t>(settings_.publish_every) == 0) {
    Timed t(profile_, ids.publish);
    publish();
  }
  if (pending_sample_) {
    for (const auto& l : sample_listeners_) l(*pending_sample_, profile_);
    pending_sample_.reset();
  }
  return true;
}

// The scheme's advance. Schemes that solve (implicit) poll stop_requested() between their
// iterations: the step's start is kept first, and put back when they stopped, so that the
// caller sees the state of the last whole step.
bool Simulator::advance_or_stop(Real h) {
  {
    Timed t(profile_, ids_->integrate);
    integrator_->advance(model_, state_, h, *this, profile_);
  }
  if (!interrupted_) {
    note_convergence();
    return true;
  }
  copy_values(step_start_, state_);
  pending_sample_.reset();
  return false;
}

// The bound on the nonlinear step's force imbalance, in units of the heaviest free point's
// weight m g, and the steps in a row above it that make a run unconverged. Measured on
// cloth_on_sphere over 3 s (one run each): VBD at 1/60 s and 1/20 s with 10 sweeps peak at 190
// and 307 (contacts sit on the force's jump); matrix_free at 1/60 s peaks at 4,300 and at
// 0.05 s at 16,600 for three separate impact steps (median 5.5, the drape ends at 0.02 J);
// matrix_free at 0.1 s stays at 1.4e5 (median) for 28 of 30 steps and ends with 144 J of
// elastic energy where the drape holds 0.02 J. A single step above the bound is an impact,
// five in a row a solve that does not converge.
const double Simulator::kUnconvergedResidual = 1e4;
const int Simulator::kUnconvergedSteps = 5;

// After an implicit step: its residual against the bound (Simulator::unconverged).
void Simulator::note_convergence() {
  if (!integrator_->uses_jacobians()) return;
  const auto& gauges = profile_.gauges();
  if (residual_gauge_ < 0)
    for (std::size_t g = 0; g < gauges.size(); ++g)
      if (gauges[g].name == "solver_residual") residual_gauge_ = int(g);
  if (residual_gauge_ < 0) return;
  const double r = gauges[std::size_t(residual_gauge_)].last;
  if (!(r > kUnconvergedResidual)) {
    streak_ = Unconverged{};
    return;
  }
  if (streak_.steps++ == 0) streak_ = {state_.step + 1, state_.time + settings_.step, 1, r};
  streak_.worst = std::max(streak_.worst, r);
  if (unconverged_) {
    ++unconverged_->steps;
    unconverged_->worst = std::max(unconverged_->worst, r);
  } else if (streak_.steps >= std::uint64_t(kUnconvergedSteps)) {
    unconverged_ = streak_;
  }
}

std::string unconverged_text(const Simulator& sim) {
  const auto& u = sim.unconverged();
  if (!u) return {};
  const SimulationSettings& s = sim.settings();
  std::ostringstream out;
  out.precision(4);
  const bool vbd = s.implicit.solver == ImplicitSolver::vbd;
  out << s.integrator << " (" << to_string(s.implicit.solver) << ") ended " << u->steps
      << " steps unconverged, the first at step " << u->first_step << " (t = " << u->first_time
      << " s): the force imbalance (solver_residual) stayed above "
      << Simulator::kUnconvergedResidual << " times a point's weight for "
      << Simulator::kUnconvergedSteps << " steps or more in a row (worst " << u->worst
      << "); the motion is damped, not accurate: reduce simulation.step or raise "
      << (vbd ? "simulation.implicit.iterations" : "simulation.implicit.newton_iterations");
  return out.str();
}

// The step's start, for advance_or_stop, when a stop can come inside the step.
void Simulator::keep_for_stop() {
  if (!stop_poll_ || !integrator_->uses_jacobians()) return;
  if (step_start_.size() != state_.size()) step_start_ = State(state_.size());
  copy_values(state_, step_start_);
}

bool Simulator::stop_requested() {
  if (!interrupted_ && stop_poll_ && stop_poll_()) interrupted_ = true;
  return interrupted_;
}

bool Simulator::run_steps(std::uint64_t n) {
  for (std::uint64_t i = 0; i < n; ++i)
    if (!step()) return false;
  return true;
}

std::span<Simulator::Installed> Simulator::stages_of(Phase p) {
  const auto lo = std::find_if(stages_.begin(), stages_.end(),
                               [&](const Installed& st) { return st.phase >= p; });
  const auto hi =
      std::find_if(lo, stages_.end(), [&](const Installed& st) { return st.phase > p; });
  // (pointer and size: the web build's libc++ has no span from an iterator pair)
  return {stages_.data() + (lo - stages_.begin()), std::size_t(hi - lo)};
}

std::span<const Simulator::Installed> Simulator::stages_of(Phase p) const {
  return const_cast<Simulator*>(this)->stages_of(p);
}

const Stage* Simulator::first_checked(std::span<const Installed> stages) {
  for (const auto& st : stages)
    if (!st.stage->reads_only()) return st.stage.get();
  return nullptr;
}

StageContext Simulator::context(const State& s) const {
  StageContext ctx;
  ctx.h = settings_.step;
  ctx.t = s.time;
  ctx.step = s.step;
  ctx.threads = threads_;
  ctx.velocity = integrator_->velocity_time(s);
  ctx.drift_after_kick = integrator_->drifts_after_kick();
  ctx.jacobians = integrator_->uses_jacobians();
  ctx.profile = const_cast<Profile*>(&profile_);  // counters only; timing stays here
  return ctx;
}

// Every force-phase stage at the state's current positions, velocities and time. Under an
// implicit scheme the contact stages find the step's contact set instead of adding forces.
void Simulator::evaluate(State& s) {
  evaluate_stages(s, true);
}

// An implicit solve's iterate: every force but the contacts, whose set stays the step's.
void Simulator::evaluate_keeping_contacts(State& s) {
  evaluate_stages(s, false);
}

void Simulator::evaluate_stages(State& s, bool find) {
  const auto& ids = *ids_;
  {
    Timed t(profile_, ids.drive);
    stages::drive(model_, s, s.time);
  }
  {
    Timed t(profile_, ids.clear);
    stages::clear_forces(s);
  }
  {
    Timed t(profile_, ids.links);
    profile_.set_count(ids.active_links, stages::link_forces(model_, s, threads_).active);
  }
  {
    Timed t(profile_, ids.fields);
    profile_.set_count(ids.wind_faces, stages::field_forces(model_, s, threads_));
  }
  if (find) contacts_.clear();
  const auto forces = stages_of(Phase::forces);
  if (forces.empty()) return;
  if (const Stage* checked = first_checked(forces))
    if (!stage_input_finite(s, *checked)) return;
  const StageContext ctx = context(s);
  for (auto& st : forces) {
    if (!ctx.jacobians || !st.stage->finds_contacts()) {
      Timed t(profile_, st.profile_id);
      st.stage->apply(model_, s, ctx);
    } else if (find) {
      Timed t(profile_, st.profile_id);
      st.stage->find_contacts(model_, s, ctx, contacts_);
    }
  }
}

// A solve's iterate went past what the step's search guarantees: the contact stages that can
// search again do so at s, into the arrays the set already holds.
bool Simulator::find_contacts_again(State& s, std::span<const std::uint32_t> moved) {
  const StageContext ctx = context(s);
  bool searched = false;
  for (auto& st : stages_of(Phase::forces)) {
    if (!st.stage->finds_contacts()) continue;
    Timed t(profile_, st.profile_id);
    searched = st.stage->find_contacts_again(model_, s, ctx, moved) || searched;
  }
  return searched;
}

// Response stages rewrite forces and velocities once per step, after the force pass; a
// non-finite value they leave is theirs.
void Simulator::respond() {
  const auto response = stages_of(Phase::response);
  if (response.empty()) return;
  if (!stage_input_finite(state_, *response.front().stage)) return;
  const StageContext ctx = context(state_);
  for (auto& st : response) {
    {
      Timed t(profile_, st.profile_id);
      st.stage->apply(model_, state_, ctx);
    }
    if (!all_finite(state_.f()) || !all_finite(state_.v())) {
      fail(st.stage->name(),
           "non-finite force or velocity written by stage '" + st.stage->name() + "'");
      return;
    }
  }
}

Energies Simulator::energies() {
  sync_host();
  evaluate(state_);  // synchronising staggered velocities needs the forces at x
  integrator_->synchronized_velocity(model_, state_, static_cast<Real>(settings_.step),
                                     scratch_velocity_);
  return all_energies();
}

Energies Simulator::all_energies() {
  Energies e = compute_energies(model_, state_, scratch_velocity_);
  for (Installed& st : stages_) e.contact += st.stage->energy(model_, state_);
  return e;
}

namespace {
// What the runaway check watches: kinetic + elastic + contact, and gravity's share only when it
// is not finite (a falling body is not a blow-up, an infinite potential is).
double watched_energy(const Energies& e) {
  return e.kinetic + e.elastic + e.contact + (std::isfinite(e.gravity) ? 0.0 : e.gravity);
}
}  // namespace

bool Simulator::check_energy() {
  if (blow_up_) return false;
  if (backend_) {
    check_backend_health();
    if (blow_up_) return false;
  }
  return !runaway(watched_energy(energies()));
}

void Simulator::sample_energies() {
  integrator_->synchronized_velocity(model_, state_, static_cast<Real>(settings_.step),
                                     scratch_velocity_);
  const EnergySample sample{state_.step, state_.time, all_energies()};
  if (runaway(watched_energy(sample.energies))) return;
  pending_sample_ = sample;  // handed to listeners at the end of the step, with its timings
}

// Runaway: the energy that can grow without bound (kinetic + elastic) far above anything the
// scene can supply. Gravity's share is excluded: a falling body is not a blow-up.
bool Simulator::runaway(double e) {
  if (std::isfinite(e) && e <= settings_.runaway_factor * energy_scale_) return false;
  std::ostringstream why;
  if (std::isfinite(e))
    why << "runaway energy " << e << " J (" << settings_.runaway_factor
        << " times the scene's energy scale " << energy_scale_ << " J)";
  else  // never "-nan J": say what it is
    why << "the energy is " << (std::isnan(e) ? "not a number" : "infinite")
        << " (a value of the scene overflows: masses, stiffnesses or speeds too large)";
  fail("", why.str());
  return true;
}

void Simulator::publish() {
  snapshot_.step = state_.step;
  snapshot_.time = state_.time;
  snapshot_.overlay.clear();
  // The device's buffer is current unless the host changed since the last load.
  const std::uint32_t device =
      device_snapshots_ && backend_ && !host_ahead_ ? backend_->gl_positions() : 0;
  if (device != 0) {
    snapshot_.positions.clear();
    snapshot_.device = {device, model_.points.size()};
  } else {
    sync_host();
    const auto x = state_.x();
    snapshot_.positions.assign(x.begin(), x.end());
    snapshot_.device = {};
  }
  if (overlays_ && device == 0)
    for (const Installed& st : stages_) st.stage->overlay(model_, state_, snapshot_.overlay);
  snapshot_.surfaces.clear();
  for (const Installed& st : stages_) st.stage->surfaces(state_.time, snapshot_.surfaces);
  for (const auto& l : publish_listeners_) l(snapshot_);
  ++snapshot_.frame;
}

void Simulator::publish_now() {
  publish();  // downloads the state unless it publishes the device's buffer
}

}  // namespace maille
