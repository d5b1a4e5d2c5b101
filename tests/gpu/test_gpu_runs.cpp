// Whole runs on the GPU backend against the CPU, physics on the GPU (an oscillator's period),
// determinism and resumption, the blow-up detection and the refusals.
//
// How far a GPU run may drift from the CPU run: the GPU stores x and v in float, so every step
// it perturbs the state by a rounding of relative size eps = 2^-24, and a flapping flag
// amplifies perturbations (it is chaotic over seconds). The yardstick is the CPU itself with
// the same perturbation: the CPU run whose x and v are rounded to float after every step (the
// "float-storage" run). Its distance to the CPU run, D, is what float storage alone does to
// this trajectory; the GPU also computes forces in float (a few more roundings of the same
// size per step), so it is allowed 4 D. Both distances are measured as the largest point
// distance over the run's last state.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "gpu/gpu_test_support.hpp"
#include "maille/backend.hpp"
#include "maille/gpu.hpp"
#include "maille/links/spring.hpp"
#include "maille/scene.hpp"
#include "maille/simulator.hpp"

namespace maille {
namespace {

using GpuRun = test::GpuTest;

double distance(const std::vector<Vec3>& a, const std::vector<Vec3>& b) {
  return test::max_distance(a, b);
}

// Runs `scene` on the CPU, the CPU with float storage and the GPU; checks the GPU's distance.
std::vector<Vec3> expect_within_float_storage_drift(const Scene& scene, std::uint64_t steps) {
  const auto cpu = test::run_on(scene, "cpu", steps);
  const auto rounded = test::run_on(scene, "cpu", steps, true);
  const auto gpu = test::run_on(scene, "gpu", steps);
  const double drift = distance(cpu, rounded), off = distance(cpu, gpu);
  std::printf("%s, %llu steps: GPU - CPU %.3g m, float-storage drift %.3g m (ratio %.2f)\n",
              scene.name.c_str(), static_cast<unsigned long long>(steps), off, drift, off / drift);
  EXPECT_GT(drift, 0.0);
  EXPECT_LE(off, 4 * drift + 1e-6);
  return gpu;
}

TEST_F(GpuRun, FlagInWindStaysWithinTheFloatStorageDriftOfTheCpu) {
  expect_within_float_storage_drift(test::example_scene("flag_in_wind"), 500);
}

// A lattice falling on a floor of conditional links (contacts made and broken every step).
TEST_F(GpuRun, LatticeOnAConditionalFloorStaysWithinTheFloatStorageDrift) {
  // Its bottom starts inside the floor's reach (0.06 m < threshold 0.1 m): contacts push it up
  // while it falls, made and broken from the first steps.
  const Scene s = test::example_scene(
      "jelly_cube_bounce", {"lattice[0].origin=[-0.25,0.06,-0.25]", "contact[0].method=\"links\""});
  const auto x = expect_within_float_storage_drift(s, 600);
  // The floor acts: in free fall the cube's centre would drop g t^2 / 2 = 17.7 mm in these
  // 0.06 s; its compressed contacts (4 cm into their 10 cm threshold at 3000 N/m) throw it up.
  const Group* cube = s.model.group("cube");
  ASSERT_NE(cube, nullptr);
  double y0 = 0, y1 = 0;
  for (std::uint32_t i = cube->first; i < cube->first + cube->count; ++i) {
    y0 += s.model.points.initial_position[i].y;
    y1 += x[i].y;
  }
  EXPECT_GT(y1 / cube->count, y0 / cube->count) << "the floor did not push the cube up";
}

// Driven points: the shaken flag's pole follows its path on the GPU too.
TEST_F(GpuRun, ShakenFlagStaysWithinTheFloatStorageDrift) {
  expect_within_float_storage_drift(test::example_scene("shaken_flag"), 600);
}

// Physics on the GPU: a mass on a spring from a fixed point oscillates with period
// 2 pi sqrt(m / k). Leapfrog's phase error is (omega h)^2 / 24 per radian (1.6e-6 here) and
// float storage adds about eps per step to the phase (600 steps per period: 4e-5 at most);
// zero crossings interpolated linearly over 10 periods: 2e-4 relative is ample and still 50
// times tighter than a 1 % error in k or m would give.
TEST_F(GpuRun, SpringOscillatorPeriodOnTheGpu) {
  Model m;
  const Real mass = Real(0.5), k = 200;
  m.points.add(PointKind::fixed, 1, {0, 0, 0});
  m.points.add(PointKind::free, mass, {Real(1.1), 0, 0});
  m.links.pool<Spring>().add({0, 1}, {k, 1});
  m.fields.gravity = {};
  SimulationSettings settings;
  settings.backend = "gpu";
  const double period = 2 * std::numbers::pi * std::sqrt(double(mass) / double(k));
  settings.step = period / 600;
  Simulator sim(m, settings);
  std::vector<double> crossings;
  double prev = sim.state().x()[1].x - 1;
  for (int i = 0; i < 6200; ++i) {
    ASSERT_TRUE(sim.step());
    const double u = sim.state().x()[1].x - 1;
    if (prev < 0 && u >= 0) crossings.push_back(sim.time() - settings.step * u / (u - prev));
    prev = u;
  }
  ASSERT_GE(crossings.size(), 10u);
  const double measured = (crossings.back() - crossings.front()) / double(crossings.size() - 1);
  EXPECT_NEAR(measured / period, 1.0, 2e-4);
  // The amplitude is kept (leapfrog is symplectic): 0.1 m within float storage.
  double biggest = 0;
  for (int i = 0; i < 600; ++i) {
    sim.step();
    biggest = std::max(biggest, double(sim.state().x()[1].x - 1));
  }
  EXPECT_NEAR(biggest, 0.1, 1e-4);
}

// No atomics on floats: the same steps give the same bits, and a run resumed from a downloaded
// state continues exactly (float -> double -> float is exact).
TEST_F(GpuRun, RunsAreDeterministicAndResumable) {
  const Scene scene = test::example_scene("flag_in_wind");
  SimulationSettings settings = scene.settings;
  settings.backend = "gpu";
  Simulator a(scene.model, settings);
  a.run_steps(200);
  Simulator b(scene.model, settings);
  b.run_steps(100);
  Simulator c(scene.model, settings);
  c.restore(b.state());
  c.run_steps(100);
  EXPECT_EQ(state_hash(a.state()), state_hash(c.state()));
  Simulator d(scene.model, settings);
  d.run_steps(200);
  EXPECT_EQ(state_hash(a.state()), state_hash(d.state()));
}

TEST_F(GpuRun, BlowUpIsDetectedWithItsStep) {
  auto loaded = load_scene(MAILLE_TEST_DATA "/unstable_spring.toml");
  ASSERT_TRUE(loaded) << loaded.error().to_string();
  SimulationSettings settings = loaded->settings;
  settings.backend = "gpu";
  Simulator sim(loaded->model, settings);
  bool alive = true;
  for (int i = 0; i < 20000 && alive; ++i) alive = sim.step();
  if (alive) alive = sim.check_energy();
  ASSERT_FALSE(alive);
  ASSERT_TRUE(sim.blow_up());
  EXPECT_GT(sim.blow_up()->step, 0u);
  EXPECT_NE(sim.blow_up()->message.find("step"), std::string::npos) << sim.blow_up()->message;
  std::printf("%s\n", sim.blow_up()->message.c_str());
}

TEST_F(GpuRun, WhatTheGpuCannotRunIsRefusedByName) {
  auto refused = [](const std::string& example, const std::string& integrator = {}) {
    Scene s = test::example_scene(example);
    s.settings.backend = "gpu";
    if (!integrator.empty()) s.settings.integrator = integrator;
    try {
      Simulator sim(s.model, s.settings);
    } catch (const std::invalid_argument& e) {
      return std::string(e.what());
    }
    return std::string("accepted");
  };
  // Self-collision runs on the GPU with primitive = "points" (test_gpu_self_collision.cpp
  // checks that "triangles" is refused by name).
  EXPECT_EQ(refused("flag_storm"), "accepted");
  EXPECT_NE(refused("flag_in_wind", "rk4").find("integrator 'rk4'"), std::string::npos);
  EXPECT_NE(refused("sphere_by_facets").find("stage '"), std::string::npos);
  EXPECT_EQ(refused("flag_in_wind"), "accepted");
  EXPECT_EQ(refused("flag_in_wind", "symplectic_euler"), "accepted");
}

// The host copy is refreshed only when asked, and edits reach the device.
TEST_F(GpuRun, EditsBetweenStepsReachTheDevice) {
  const Scene scene = test::example_scene("pendulum_chain");
  SimulationSettings settings = scene.settings;
  settings.backend = "gpu";
  Simulator sim(scene.model, settings);
  sim.run_steps(10);
  State& s = sim.state_for_editing();
  for (Vec3& v : s.v()) v = {};
  for (std::size_t i = 0; i < s.size(); ++i) s.x()[i] = sim.model().points.initial_position[i];
  sim.edit_parameters([](Model& m) { m.fields.gravity = {}; });
  sim.run_steps(10);
  // No gravity, at rest in the initial (rest) shape: nothing moves.
  for (std::size_t i = 0; i < s.size(); ++i)
    EXPECT_LE(norm(sim.state().x()[i] - sim.model().points.initial_position[i]), 1e-6);
}

}  // namespace
}  // namespace maille
