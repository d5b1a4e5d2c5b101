// An example scene run for a while, for tests that need a cloth in a real, curved state (the
// smooth-surface tests on the CPU and on the GPU). Needs MAILLE_SOURCE_DIR.
#pragma once

#include <stdexcept>
#include <string>
#include <vector>

#include "maille/scene.hpp"
#include "maille/simulator.hpp"

namespace maille::test {

// examples/NAME.toml loaded into `scene`, then `steps` steps on one thread: the positions.
inline std::vector<Vec3> run_example(const std::string& name, std::uint64_t steps, Scene& scene) {
  auto loaded = load_scene(std::string(MAILLE_SOURCE_DIR "/examples/") + name + ".toml");
  if (!loaded) throw std::runtime_error(loaded.error().to_string());
  scene = std::move(loaded.value());
  SimulationSettings settings = scene.settings;
  settings.threads = 1;
  Simulator sim(scene.model, settings);
  sim.run_steps(steps);
  return {sim.state().x().begin(), sim.state().x().end()};
}

}  // namespace maille::test
