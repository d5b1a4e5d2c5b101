// The [simulation] settings, each with whether a running simulator takes a new value of it: the
// one declaration that live edits read (the Python module's Simulation.set refuses the others
// and applies these). A simulator is built with its cadences, threads, runaway factor, backend
// and device; between two steps it takes a new step, scheme and implicit solver's settings
// (Simulator::set_step, set_integrator, set_implicit); the duration is the program's (how far a
// run goes), never the simulator's.
#pragma once

#include <span>
#include <string>
#include <string_view>

#include "maille/simulator.hpp"

namespace maille {

struct SimulationSetting {
  std::string_view key;  // its key under [simulation] ("implicit.*": the table's keys)
  bool live;             // a running simulator takes a new value
  bool (*differs)(const SimulationSettings&, const SimulationSettings&);
};
// Every [simulation] key, the live ones first. (SimulationSettings::disabled_stages is no scene
// key: programs choose it when they build the simulator.)
std::span<const SimulationSetting> simulation_settings();

// The first key a running simulator cannot take whose value differs between `running` and
// `wanted` ("output_every"), or empty when every difference can be applied.
std::string_view fixed_setting_changed(const SimulationSettings& running,
                                       const SimulationSettings& wanted);
// The live keys with their table, for messages: "simulation.step, simulation.integrator, ...".
std::string live_setting_keys();
// Gives `sim` the live settings of `wanted` that differ from its own: the implicit solver's
// first (a switch to implicit_euler builds the solver with them), then the scheme, then the
// step. Throws std::invalid_argument as those setters do.
void apply_live_settings(Simulator& sim, const SimulationSettings& wanted);

}  // namespace maille
