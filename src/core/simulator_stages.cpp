// The simulator's stage lists: installing the model's stages and the caller's, removing them,
// the options and variants tools switch live, and the warnings a run prints about them.
#include <algorithm>
#include <stdexcept>
#include <string>
#include <vector>

#include "maille/simulator.hpp"
#include "maille/stage_keys.hpp"

namespace maille {

void Simulator::install_model_stages() {
  for (std::size_t i = 0; i < model_.stages.size(); ++i) {
    const StageSpec& spec = model_.stages[i];
    const auto& off = settings_.disabled_stages;
    if (std::find(off.begin(), off.end(), spec.name) != off.end()) continue;
    std::unique_ptr<Stage> stage = spec.make(model_);
    check_stage(*stage);
    add_installed(std::move(stage), true, static_cast<int>(i));
  }
}

void Simulator::check_stage(Stage& stage) const {
  if (backend_) check_backend(*integrator_, &stage);
  if (const std::string why = integrator_->check_stage(stage); !why.empty())
    throw std::invalid_argument(why);
  if (stage.phase() == Phase::response && integrator_->response_timing() == ResponseTiming::refused)
    throw std::invalid_argument("stage '" + stage.name() +
                                "' rewrites forces and velocities after the fact; " +
                                std::string(integrator_->name()) +
                                " evaluates forces at intermediate states and cannot be combined "
                                "with it (use leapfrog, symplectic_euler, explicit_euler or "
                                "implicit_euler)");
}

void Simulator::add_stage(std::unique_ptr<Stage> stage) {
  check_stage(*stage);
  add_installed(std::move(stage), false);
}

void Simulator::remove_stage(const Stage* stage) {
  if (std::erase_if(stages_, [&](const Installed& st) { return st.stage.get() == stage; })) {
    host_ahead_ = true;  // as when adding: a device backend reloads its list
    restimate_stability();
  }
}

void Simulator::add_installed(std::unique_ptr<Stage> stage, bool from_model, int spec) {
  const int id = profile_.stage(stage->name());
  const Phase phase = stage->phase();
  // At the end of its phase's range: the list stays in step order.
  const auto at = std::find_if(stages_.begin(), stages_.end(),
                               [&](const Installed& st) { return st.phase > phase; });
  stages_.insert(at, {std::move(stage), phase, id, from_model, spec});
  host_ahead_ = true;  // a device backend is loaded again with the new list before the next step
  restimate_stability();
}

std::vector<Simulator::StageOptions> Simulator::stage_options() const {
  std::vector<StageOptions> out;
  for (const auto& st : stages_) {
    auto o = st.stage->options();
    if (st.spec >= 0)
      if (const StageSpec& spec = model_.stages[st.spec]; spec.vary)
        o.insert(o.begin(), {spec.variant_option, spec.variants, spec.variant});
    if (!o.empty()) out.push_back({st.stage->name(), std::move(o)});
  }
  return out;
}

// [simulation.implicit] keys set (away from their defaults) that the running scheme or solver
// does not read: accepted, since the viewer and live edits switch solvers and each keeps its
// own settings, but said, so that `tolerance` under vbd does not pass for a setting in effect.
namespace {
std::vector<std::string> unused_implicit_keys(const SimulationSettings& s) {
  std::vector<std::string> out;
  const ImplicitSettings defaults{};
  const bool implicit = s.integrator == kImplicitEuler;
  const std::string solver(to_string(s.implicit.solver));
  for (const auto& k : implicit_keys()) {
    if (!k.value || k.value(s.implicit) == k.value(defaults)) continue;
    const std::string_view methods = k.info.methods;
    if (implicit && (methods.empty() || methods.find(solver) != std::string_view::npos)) continue;
    out.push_back("simulation.implicit." + std::string(k.key) + " = " + k.value(s.implicit) +
                  " is not used " +
                  (implicit
                       ? "by solver \"" + solver + "\" (it is used by " + std::string(methods) + ")"
                       : "by integrator \"" + s.integrator + "\" (implicit_euler only)"));
  }
  return out;
}
}  // namespace

std::vector<std::string> Simulator::stage_warnings() const {
  std::vector<std::string> out = unused_implicit_keys(settings_);
  for (const auto& st : stages_)
    for (const std::string& w : st.stage->warnings(settings_))
      out.push_back(st.stage->name() + ": " + w);
  return out;
}

// Installs another variant of a model stage in place of the current one; nothing changes when
// the variant is unknown or the scheme refuses it.
void Simulator::switch_variant(std::size_t spec_index, const std::string& value) {
  const StageSpec& spec = model_.stages[spec_index];
  if (std::find(spec.variants.begin(), spec.variants.end(), value) == spec.variants.end())
    throw std::invalid_argument("stage '" + spec.name + "': no " + spec.variant_option + " '" +
                                value + "'");
  StageSpec next = spec.vary(value);
  std::unique_ptr<Stage> stage = next.make(model_);
  check_stage(*stage);
  std::erase_if(stages_, [&](const Installed& st) { return st.spec == int(spec_index); });
  model_.stages[spec_index] = std::move(next);
  add_installed(std::move(stage), true, static_cast<int>(spec_index));
}

void Simulator::set_stage_option(const std::string& stage, const std::string& option,
                                 const std::string& value) {
  for (auto& st : stages_)
    if (st.stage->name() == stage) {
      if (st.spec >= 0 && model_.stages[st.spec].vary &&
          model_.stages[st.spec].variant_option == option)
        return switch_variant(static_cast<std::size_t>(st.spec), value);
      // A backend that cannot run the stage as changed refuses the option: it is set back.
      std::string before;
      for (const StageOption& o : st.stage->options())
        if (o.name == option) before = o.value;
      st.stage->set_option(option, value);
      if (backend_) try {
          check_backend(*integrator_);
        } catch (...) {
          st.stage->set_option(option, before);
          throw;
        }
      return;
    }
  throw std::invalid_argument("no stage named '" + stage + "'");
}

}  // namespace maille
