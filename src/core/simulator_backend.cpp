// The step on a device backend (backend.hpp): the same order as Simulator::step, with the
// forces, the integration and the health flag on the device. The host copy of the state is
// refreshed only when something needs it: an energy sample, a snapshot, an edit, the end of a
// run (sync_host); host-side changes reload the device before the next step (host_ahead_).
#include <sstream>
#include <stdexcept>

#include "maille/simulator.hpp"
#include "simulator_detail.hpp"
#include "stages.hpp"

namespace maille {

using detail::Timed;

void Simulator::make_backend() {
  const BackendRegistry::Entry* entry = BackendRegistry::global().find(settings_.backend);
  if (!entry)
    throw std::invalid_argument("unknown backend '" + settings_.backend +
                                "' (this program has: " + BackendRegistry::global().names() + ")");
  if (!entry->make) return;  // the CPU: the simulator's own path
  // A device that cannot start (no OpenGL 4.5, no such EGL device) is a set-up the simulator
  // refuses, like a stage the backend lacks: std::invalid_argument, with the cause.
  std::unique_ptr<Backend> made;
  try {
    made = entry->make(settings_.backend_options);
  } catch (const std::runtime_error& e) {
    throw std::invalid_argument("backend " + settings_.backend + " cannot start: " + e.what());
  }
  backend_ = std::move(made);
  try {
    check_backend(*integrator_);
  } catch (...) {
    backend_.reset();
    throw;
  }
}

void Simulator::check_backend(const Integrator& scheme, const Stage* extra) const {
  std::vector<const Stage*> stages = installed_stages();
  if (extra) stages.push_back(extra);
  if (const std::string why = backend_->refuses(model_, scheme, stages); !why.empty())
    throw std::invalid_argument("backend " + std::string(backend_->name()) + ": " + why);
}

void Simulator::sync_host() const {
  if (!backend_ || !device_ahead_) return;
  backend_->download(state_);
  device_ahead_ = false;
}

void Simulator::wait() {
  if (backend_) backend_->finish();
}

// A non-finite value flagged on the device: the state is brought back and the report names the
// step at which the flag was first raised (checks run at the sampling and publishing cadence).
void Simulator::check_backend_health() {
  const std::uint64_t first = backend_->first_non_finite();
  if (first == 0) return;
  sync_host();
  std::ostringstream why;
  why << "non-finite position or velocity computed on the " << backend_->name()
      << " backend, first at step " << first << " (t = " << double(first) * settings_.step << " s)";
  fail("", why.str());
  blow_up_->step = first;
}

// The implicit solver's step on the device, with the CPU's stats columns (implicit_euler.cpp):
// the counters and the residual are read back when this step's sample is pending (the rows
// that stats.csv writes), so the device is not waited for every step.
void Simulator::implicit_step_on_backend(Real h) {
  if (device_ids_.iterations < 0) {
    device_ids_.iterations = profile_.counter("solver_iterations");
    device_ids_.residual = profile_.gauge("solver_residual");
    device_ids_.colours = profile_.counter("vbd_colours");
    device_ids_.resets = profile_.counter("vbd_acceleration_resets");
    device_ids_.refreshes = profile_.counter("vbd_candidate_refreshes");  // none: static colours
  }
  const bool measure = pending_sample_.has_value();
  find_contacts_for_backend();
  const DeviceImplicitStep r = backend_->implicit_step(model_, *integrator_, state_.time, h,
                                                       state_.step + 1, measure, contacts_);
  profile_.set_count(device_ids_.iterations, r.iterations);
  profile_.set_count(device_ids_.colours, r.colours);
  if (r.acceleration_resets) profile_.set_count(device_ids_.resets, *r.acceleration_resets);
  if (r.residual) profile_.set_gauge(device_ids_.residual, *r.residual);
}

// The stages that put point pairs or stencils into the contact set find them on the host at
// x_n (the state brought back from the device), as the CPU's step does; the device uploads them
// and evaluates them by the shared laws at every iterate. Stages of obstacle contacts
// (geometric obstacles) have device versions of their own and are not asked.
void Simulator::find_contacts_for_backend() {
  contacts_.clear();
  bool synced = false;
  for (auto& st : stages_of(Phase::forces)) {
    const ContactKinds kinds = st.stage->contacts_found();
    if (!has(kinds, ContactKinds::pairs) && !has(kinds, ContactKinds::stencils)) continue;
    if (!synced) sync_host(), synced = true;
    const StageContext ctx = context(state_);
    Timed t(profile_, st.profile_id);
    st.stage->find_contacts(model_, state_, ctx, contacts_);
  }
}

bool Simulator::step_on_backend() {
  const auto& ids = *ids_;
  if (host_ahead_) {
    sync_host();
    backend_->load(model_, state_, installed_stages());
    host_ahead_ = false;
  }
  profile_.begin_step();
  const Real h = static_cast<Real>(settings_.step);
  const bool driven = !model_.drives.empty();
  if (driven) {
    Timed t(profile_, ids.drive);
    backend_->drive(model_, state_.time);
  }
  // A step the backend makes whole evaluates what it needs itself: the force pass runs only for
  // the energy sample.
  const bool sampling = state_.step % static_cast<std::uint64_t>(settings_.sample_every) == 0;
  if (sampling || !backend_->steps(*integrator_)) {
    Timed t(profile_, ids.links);  // every force of the step, on the device
    backend_->evaluate(model_, state_.time);
  }
  // Energies at t_n need the forces at t_n (a staggered scheme's velocities are synchronised
  // with them), so the sample downloads them before the integration.
  if (sampling) {
    device_ahead_ = true;
    sync_host();
    if (!inspect_stages(true)) return false;  // every_step checks at this cadence here
    sample_energies();
    if (blow_up_) return false;
  }
  {
    Timed t(profile_, ids.integrate);
    if (backend_->steps(*integrator_)) {
      implicit_step_on_backend(h);
    } else {
      const std::optional<Integrator::KickDrift> k = integrator_->kick_drift_step(state_, h);
      backend_->integrate(k->kick, k->drift, state_.step + 1);
      state_.history = k->history_after;
    }
  }
  state_.time += settings_.step;
  state_.step += 1;
  device_ahead_ = true;
  if (driven) {
    Timed t(profile_, ids.after);
    backend_->drive(model_, state_.time);
  }
  const bool publishing = state_.step % static_cast<std::uint64_t>(settings_.publish_every) == 0;
  if (publishing || pending_sample_) {
    Timed t(profile_, ids.health);
    check_backend_health();
    if (blow_up_) return false;
  }
  if (publishing) {
    Timed t(profile_, ids.publish);
    publish();  // downloads the state unless it publishes the device's buffer
  }
  if (pending_sample_) {
    for (const auto& l : sample_listeners_) l(*pending_sample_, profile_);
    pending_sample_.reset();
  }
  return true;
}

}  // namespace maille
