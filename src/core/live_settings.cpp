#include "maille/live_settings.hpp"

namespace maille {

namespace {

template <auto member>
bool differs(const SimulationSettings& a, const SimulationSettings& b) {
  return !(a.*member == b.*member);
}

bool device_differs(const SimulationSettings& a, const SimulationSettings& b) {
  return a.backend_options.device != b.backend_options.device;
}

constexpr SimulationSetting kSettings[] = {
    {"step", true, differs<&SimulationSettings::step>},
    {"integrator", true, differs<&SimulationSettings::integrator>},
    {"implicit.*", true, differs<&SimulationSettings::implicit>},
    {"duration", true, differs<&SimulationSettings::duration>},
    {"output_every", false, differs<&SimulationSettings::publish_every>},
    {"sample_every", false, differs<&SimulationSettings::sample_every>},
    {"threads", false, differs<&SimulationSettings::threads>},
    {"runaway_factor", false, differs<&SimulationSettings::runaway_factor>},
    {"backend", false, differs<&SimulationSettings::backend>},
    {"gpu_device", false, device_differs},
};

}  // namespace

std::span<const SimulationSetting> simulation_settings() {
  return kSettings;
}

std::string_view fixed_setting_changed(const SimulationSettings& running,
                                       const SimulationSettings& wanted) {
  for (const SimulationSetting& s : kSettings)
    if (!s.live && s.differs(running, wanted)) return s.key;
  return {};
}

std::string live_setting_keys() {
  std::string out;
  for (const SimulationSetting& s : kSettings)
    if (s.live) out += (out.empty() ? "simulation." : ", simulation.") + std::string(s.key);
  return out;
}

void apply_live_settings(Simulator& sim, const SimulationSettings& wanted) {
  if (!(wanted.implicit == sim.settings().implicit)) sim.set_implicit(wanted.implicit);
  if (wanted.integrator != sim.settings().integrator) sim.set_integrator(wanted.integrator);
  if (wanted.step != sim.settings().step) sim.set_step(wanted.step);
}

}  // namespace maille
