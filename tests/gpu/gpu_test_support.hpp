// What the GPU tests share: float's rounding unit, the fixture that registers the backend, the
// extents their float-derived bounds start from, and the "float-storage" rounding of a state
// (the CPU run that the whole-run tests measure the GPU's drift against), and a run on a backend.
#pragma once

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <span>
#include <stdexcept>
#include <string>
#include <vector>

#include "maille/gpu.hpp"
#include "maille/scene.hpp"
#include "maille/simulator.hpp"
#include "maille/state.hpp"

namespace maille::test {

inline constexpr double kFloatEps = 5.96e-8;  // float's unit roundoff, 2^-24

// An example scene (examples/NAME.toml) with `--set` overrides; throws its error when it fails.
inline Scene example_scene(const std::string& name, const std::vector<std::string>& sets = {}) {
  auto s = load_scene(std::string(MAILLE_SOURCE_DIR "/examples/") + name + ".toml", sets);
  if (!s) throw std::runtime_error(s.error().to_string());
  return std::move(s.value());
}

class GpuTest : public ::testing::Test {
 protected:
  static void SetUpTestSuite() { gpu::register_backend(); }
};

// The largest coordinate (X of the bounds) and the largest norm (V).
inline double max_abs(std::span<const Vec3> x) {
  double m = 0;
  for (const Vec3& p : x) m = std::max({m, std::abs(p.x), std::abs(p.y), std::abs(p.z)});
  return m;
}
inline double max_norm(std::span<const Vec3> v) {
  double m = 0;
  for (const Vec3& p : v) m = std::max(m, double(norm(p)));
  return m;
}

// The largest distance between corresponding points of two runs.
inline double max_distance(std::span<const Vec3> a, std::span<const Vec3> b) {
  double d = 0;
  for (std::size_t i = 0; i < a.size(); ++i) d = std::max(d, double(norm(a[i] - b[i])));
  return d;
}

// x and v rounded to float, as the GPU stores them.
inline void round_to_float(State& s) {
  for (Vec3& x : s.x()) x = {Real(float(x.x)), Real(float(x.y)), Real(float(x.z))};
  for (Vec3& v : s.v()) v = {Real(float(v.x)), Real(float(v.y)), Real(float(v.z))};
}

// `steps` steps of `scene` on `backend`, one thread (with float_storage, x and v rounded to
// float after each step: the CPU run whose distance from the exact one is the float-storage
// drift); every step must succeed and the energy stay finite. Returns the positions.
inline std::vector<Vec3> run_on(const Scene& scene, const std::string& backend, std::uint64_t steps,
                                bool float_storage = false) {
  SimulationSettings settings = scene.settings;
  settings.backend = backend;
  settings.threads = 1;
  Simulator sim(scene.model, settings);
  for (std::uint64_t k = 0; k < steps; ++k) {
    EXPECT_TRUE(sim.step()) << backend << " step " << k;
    if (float_storage) round_to_float(sim.state_for_editing());
  }
  EXPECT_TRUE(sim.check_energy());
  return {sim.state().x().begin(), sim.state().x().end()};
}

}  // namespace maille::test
