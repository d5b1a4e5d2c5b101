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

#include "stages.hpp"

namespace maille {

namespace {

// Below this many points a step is a few microseconds and threads cost more than they give.
constexpr std::uint32_t kParallelThreshold = 4096;

// Times a block into a profile stage.
class Timed {
 public:
  Timed(Profile& p, int stage) : p_(p), stage_(stage), t0_(std::chrono::steady_clock::now()) {}
  ~Timed() {
    const auto dt = std::chrono::steady_clock::now() - t0_;
    p_.add_time(stage_, static_cast<double>(std::chrono::nanoseconds(dt).count()));
  }
  Timed(const Timed&) = delete;
  Timed& operator=(const Timed&) = delete;

 private:
  Profile& p_;
  int stage_;
  std::chrono::steady_clock::time_point t0_;
};

}  // namespace

struct Simulator::StageIds {
  int drive, clear, links, fields, integrate, after, health, publish;
  int active_links, wind_faces;
  std::vector<int> force_stages, after_stages;
};

Simulator::Simulator(Model model, SimulationSettings settings)
    : model_(std::move(model)), settings_(std::move(settings)), ids_(std::make_unique<StageIds>()) {
  if (!(settings_.step > 0)) throw std::invalid_argument("step must be > 0");
  if (settings_.publish_every < 1) throw std::invalid_argument("publish_every must be >= 1");
  if (settings_.sample_every < 0) throw std::invalid_argument("sample_every must be >= 0");
  if (settings_.sample_every == 0) settings_.sample_every = settings_.publish_every;
  const auto* entry = IntegratorRegistry::builtin().find(settings_.integrator);
  if (!entry)
    throw std::invalid_argument("unknown integrator '" + settings_.integrator +
                                "' (known: " + IntegratorRegistry::builtin().names() + ")");
  integrator_ = entry->make(settings_.implicit);

  const std::uint32_t n = model_.points.size();
#ifdef _OPENMP
  const int cores = omp_get_num_procs();
#else
  const int cores = 1;
#endif
  threads_ = settings_.threads > 0 ? settings_.threads : (n >= kParallelThreshold ? cores : 1);
  integrator_->set_threads(threads_);
  model_.prepare();
  if (const std::string why = integrator_->check(model_); !why.empty())
    throw std::invalid_argument(why);
  stability_ = estimate_stability(model_, *integrator_);

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
  reset();
}

Simulator::~Simulator() = default;

void Simulator::reset() {
  const std::uint32_t n = model_.points.size();
  state_ = State(n);
  std::copy(model_.points.initial_position.begin(), model_.points.initial_position.end(),
            state_.x().begin());
  std::copy(model_.points.initial_velocity.begin(), model_.points.initial_velocity.end(),
            state_.v().begin());
  stages::drive(model_, state_, 0);
  integrator_->reset();
  blow_up_.reset();
  pending_sample_.reset();
  snapshot_ = Snapshot{};
  scratch_velocity_.assign(n, Vec3{});
  energy_scale_ = energy_scale();
}

void Simulator::add_force_stage(std::unique_ptr<ForceStage> stage) {
  if (stage->rewrites_state() && !integrator_->accepts_state_rewrites())
    throw std::invalid_argument("stage '" + stage->name() +
                                "' rewrites forces and velocities after the fact; " +
                                std::string(integrator_->name()) +
                                " evaluates forces at intermediate states and cannot be combined "
                                "with it (use leapfrog, symplectic_euler or explicit_euler)");
  ids_->force_stages.push_back(profile_.stage(stage->name()));
  force_stages_.push_back(std::move(stage));
}

void Simulator::add_after_integration(std::unique_ptr<AfterIntegrationStage> stage) {
  ids_->after_stages.push_back(profile_.stage(stage->name()));
  after_stages_.push_back(std::move(stage));
}

void Simulator::on_publish(SnapshotListener listener) {
  publish_listeners_.push_back(std::move(listener));
}

void Simulator::on_sample(std::function<void(const EnergySample&, const Profile&)> listener) {
  sample_listeners_.push_back(std::move(listener));
}

void Simulator::set_step(double h) {
  if (!(h > 0)) throw std::invalid_argument("step must be > 0");
  settings_.step = h;  // leapfrog re-primes by itself: its kick spans (h_old + h_new) / 2
}

// The step, as a table of contents. Energies are sampled between the force pass and the
// integration, when forces and (synchronised) velocities belong to the same time t_n.
bool Simulator::step() {
  if (blow_up_) return false;
  profile_.begin_step();
  const auto& ids = *ids_;
  const Real h = static_cast<Real>(settings_.step);
  evaluate(state_);
  if (state_.step % static_cast<std::uint64_t>(settings_.sample_every) == 0) sample_energies();
  if (blow_up_) return false;
  {
    Timed t(profile_, ids.integrate);
    integrator_->advance(model_, state_, h, *this, profile_);
  }
  state_.time += settings_.step;
  state_.step += 1;
  {
    Timed t(profile_, ids.after);
    stages::drive(model_, state_, state_.time);
  }
  for (std::size_t k = 0; k < after_stages_.size(); ++k) {
    Timed t(profile_, ids.after_stages[k]);
    after_stages_[k]->apply(model_, state_, profile_);
  }
  {
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

bool Simulator::run_steps(std::uint64_t n) {
  for (std::uint64_t i = 0; i < n; ++i)
    if (!step()) return false;
  return true;
}

// Every force stage at the state's current positions, velocities and time.
void Simulator::evaluate(State& s) {
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
  for (std::size_t k = 0; k < force_stages_.size(); ++k) {
    Timed t(profile_, ids.force_stages[k]);
    force_stages_[k]->apply(model_, s, profile_);
  }
}

Energies Simulator::energies() {
  evaluate(state_);  // synchronising staggered velocities needs the forces at x
  integrator_->synchronized_velocity(model_, state_, static_cast<Real>(settings_.step),
                                     scratch_velocity_);
  return compute_energies(model_, state_, scratch_velocity_);
}

void Simulator::sample_energies() {
  integrator_->synchronized_velocity(model_, state_, static_cast<Real>(settings_.step),
                                     scratch_velocity_);
  const EnergySample sample{state_.step, state_.time,
                            compute_energies(model_, state_, scratch_velocity_)};
  // Runaway: the energy that can grow without bound (kinetic + elastic) far above anything
  // the scene can supply. Gravity's share is excluded: a falling body is not a blow-up.
  const double e = sample.energies.kinetic + sample.energies.elastic;
  if (!std::isfinite(e) || e > settings_.runaway_factor * energy_scale_) {
    std::ostringstream why;
    why << "runaway energy " << e << " J (" << settings_.runaway_factor
        << " times the scene's energy scale " << energy_scale_ << " J)";
    fail("", why.str());
    return;
  }
  pending_sample_ = sample;  // handed to listeners at the end of the step, with its timings
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
  return e0 + free_mass * (norm(model_.fields.gravity) * extent + 0.5 * speed2 * 4);
}

// Every step: one pass summing positions and velocities; a NaN or infinity anywhere makes the
// sum non-finite. Cheap (vectorised, ~0.3 ns per point), so a blow-up is caught at its step.
void Simulator::check_health() {
  const auto x = state_.x();
  const auto v = state_.v();
  Real sum = 0;
  const Real* xs = &x.data()->x;
  const Real* vs = &v.data()->x;
  const std::size_t n = 3 * x.size();
#pragma omp simd reduction(+ : sum)
  for (std::size_t i = 0; i < n; ++i) sum += xs[i] * 0 + vs[i] * 0;  // NaN/inf survive "* 0"
  if (std::isfinite(sum)) return;
  std::size_t bad = 0;
  while (bad < x.size() && is_finite(x[bad]) && is_finite(v[bad])) ++bad;
  std::ostringstream why;
  why << "non-finite position or velocity at point " << bad << " ("
      << to_string(model_.points.kind[bad]) << ")";
  fail("", why.str());
}

// Names the brick kind where a blow-up started: the link pool whose worst link is the most
// broken (non-finite, or stretched furthest from its rest length), with the stability hint.
void Simulator::fail(std::string module, std::string detail) {
  std::ostringstream msg;
  msg << "blow-up detected at step " << state_.step << " (t = " << state_.time << " s): " << detail;
  WorstLink worst{0, {}, -1};
  std::string worst_kind;
  for (const auto& pool : model_.links.pools()) {
    if (pool->size() == 0) continue;
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

void Simulator::publish() {
  const auto x = state_.x();
  snapshot_.step = state_.step;
  snapshot_.time = state_.time;
  snapshot_.positions.assign(x.begin(), x.end());
  for (const auto& l : publish_listeners_) l(snapshot_);
  ++snapshot_.frame;
}

void Simulator::publish_now() {
  publish();
}

}  // namespace maille
