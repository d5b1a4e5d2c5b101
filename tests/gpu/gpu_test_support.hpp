// What the GPU tests share: float's rounding unit, the fixture that registers the backend, the
// extents their float-derived bounds start from, and the "float-storage" rounding of a state
// (the CPU run that the whole-run tests measure the GPU's drift against), a run on a backend, and
// VBD's step-by-step parity with the CPU.
#pragma once

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
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

// Implicit Euler by VBD as both backends run it: 10 sweeps with Chebyshev's acceleration (0.9),
// no coarse correction (the GPU has none), one thread, no sampling.
inline SimulationSettings vbd_settings(const Scene& s, const std::string& backend,
                                       double h = 1.0 / 60) {
  SimulationSettings st = s.settings;
  st.step = h;
  st.integrator = "implicit_euler";
  st.implicit.solver = ImplicitSolver::vbd;
  st.implicit.iterations = 10;
  st.implicit.acceleration = 0.9;
  st.implicit.coarse = VbdCoarse::off;
  st.backend = backend;
  st.threads = 1;
  st.publish_every = 1 << 30;
  st.sample_every = 1 << 30;
  return st;
}

inline std::vector<Vec3> positions(const Simulator& sim) {
  return {sim.state().x().begin(), sim.state().x().end()};
}

// Each GPU step starts from the CPU's state (x, v and the guess's memory), `steps` steps of VBD
// at h (vbd_settings): the GPU's step within the rounding bound (8 roundings per update
// and sweep, of the largest coordinate) plus twice the CPU's own distance to the converged step,
// measured by the CPU with 200 sweeps from the same state. Where a contact's decision (a Newton
// step that starts or leaves one, the acceleration's fallback) goes the other way on float
// positions, the GPU's iterate is another of the same step, no worse converged than the CPU's:
// both lie within their convergence error of the step's solution. Prints the worst distance over
// its allowance; returns how many steps needed more than rounding.
inline int expect_each_step_matches(const Scene& s, int steps, const char* what,
                                    double h = 1.0 / 60) {
  constexpr double kRoundingsPerUpdate = 8;
  const SimulationSettings settings = vbd_settings(s, "cpu", h);
  SimulationSettings fine_settings = settings;
  fine_settings.implicit.iterations = 200;
  Simulator cpu(s.model, settings), gpu(s.model, vbd_settings(s, "gpu", h)),
      fine(s.model, fine_settings);
  double worst_ratio = 0, worst = 0;
  int beyond_rounding = 0;
  for (int k = 0; k < steps; ++k) {
    gpu.restore(cpu.state(), 0);
    fine.restore(cpu.state(), 0);
    if (!cpu.step() || !fine.step() || !gpu.step()) {
      ADD_FAILURE() << what << ": step " << k << " failed"
                    << (gpu.blow_up() ? ": " + gpu.blow_up()->message : std::string());
      return steps;
    }
    const auto xc = positions(cpu);
    const double off = max_distance(xc, positions(gpu));
    const double bound =
        kRoundingsPerUpdate * kFloatEps * max_abs(xc) * settings.implicit.iterations;
    const double allowed = bound + 2 * max_distance(xc, positions(fine));
    if (off > bound) ++beyond_rounding;
    EXPECT_LE(off, allowed) << what << ", step " << k;
    worst_ratio = std::max(worst_ratio, off / allowed);
    worst = std::max(worst, off);
  }
  std::printf(
      "%s, one step at a time at %.4g s: GPU - CPU at most %.3g m, %.3g of its allowance; %d of "
      "%d steps beyond the rounding bound\n",
      what, h, worst, worst_ratio, beyond_rounding, steps);
  return beyond_rounding;
}

}  // namespace maille::test
