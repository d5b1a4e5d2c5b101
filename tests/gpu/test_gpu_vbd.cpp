// Implicit Euler by vertex block descent on the GPU backend (src/gpu/gpu_vbd.hpp) against the
// CPU's solver (src/integrators/implicit_vbd.cpp): same scene, same sweeps and acceleration.
//
// How far the GPU may be from the CPU. Both run the same Gauss-Seidel sweeps in the same
// colour order (the same greedy colouring), so they differ only by rounding: the GPU stores x
// and v in float and computes in float. A point's Newton step is x += H^-1 g with g a sum of
// terms of size up to m |y - x| / h^2 + the links' forces; each float operation errs by at most
// eps = 2^-24 of its operands, and the sweep contracts (H^-1 scales g back to a position), so
// one sweep leaves each point within a few eps of the coordinates' scale X of where exact
// arithmetic would put it: the storage's own rounding, eps X, times the few roundings of an
// update. Those errors are not amplified by the damped cloth (the sweeps pull them back toward
// the step's solution), so over S sweeps in all they add up at most as S independent
// roundings, c eps X S with c = 8 roundings per update (the g terms, the 3x3 solve, the store);
// the tests check that bound and print the measured distance.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "gpu/gpu_test_support.hpp"
#include "maille/backend.hpp"
#include "maille/builders.hpp"
#include "maille/gpu.hpp"
#include "maille/links/spring.hpp"
#include "maille/scene.hpp"
#include "maille/simulator.hpp"

namespace maille {
namespace {

using GpuVbd = test::GpuTest;

constexpr double kRoundingsPerUpdate = 8;

// A 12 x 12 cloth, 0.6 m square, hanging from its pole (as tests/physics/test_vbd.cpp's,
// smaller: llvmpipe on two cores).
Model hanging_cloth() {
  Model m;
  FlagParams p;
  p.nx = 12;
  p.ny = 12;
  p.width = 0.6;
  p.height = 0.6;
  p.mass = 0.2;
  build_flag(m, p, "cloth");
  return m;
}

SimulationSettings vbd(double h, int iterations, double acceleration, const std::string& backend) {
  SimulationSettings s;
  s.step = h;
  s.integrator = "implicit_euler";
  s.implicit.solver = ImplicitSolver::vbd;
  s.implicit.iterations = iterations;
  s.implicit.acceleration = acceleration;
  s.implicit.coarse = VbdCoarse::off;  // the GPU has no coarse correction (refused: below)
  s.backend = backend;
  s.threads = 1;
  s.publish_every = 1 << 30;
  s.sample_every = 1 << 30;
  return s;
}

std::vector<Vec3> positions(const Simulator& sim) {
  return {sim.state().x().begin(), sim.state().x().end()};
}

// The bound of the header: c eps X S, X the largest coordinate, S the sweeps of the run.
double float_bound(const std::vector<Vec3>& x, std::uint64_t steps, int iterations) {
  return kRoundingsPerUpdate * test::kFloatEps * test::max_abs(x) * double(steps) *
         double(iterations);
}

// Runs the model on both backends and checks the distance against the float bound.
void expect_parity(const Model& m, const SimulationSettings& cpu_settings, std::uint64_t steps,
                   const char* what) {
  SimulationSettings gpu_settings = cpu_settings;
  gpu_settings.backend = "gpu";
  Simulator cpu(m, cpu_settings), gpu(m, gpu_settings);
  ASSERT_TRUE(cpu.run_steps(steps));
  ASSERT_TRUE(gpu.run_steps(steps)) << gpu.blow_up()->message;
  const auto xc = positions(cpu), xg = positions(gpu);
  const double moved = test::max_distance(xc, m.points.initial_position);
  const double off = test::max_distance(xc, xg);
  const double bound = float_bound(xc, steps, cpu_settings.implicit.iterations);
  std::printf("%s, %llu steps: GPU - CPU %.3g m (bound %.3g m, moved %.3g m)\n", what,
              static_cast<unsigned long long>(steps), off, bound, moved);
  EXPECT_GT(moved, 10 * bound) << "the run must move the points well beyond the bound";
  EXPECT_LE(off, bound);
}

TEST_F(GpuVbd, MatchesTheCpuOnAHangingCloth) {
  expect_parity(hanging_cloth(), vbd(1.0 / 60, 10, 0.9, "cpu"), 20, "hanging cloth");
}

TEST_F(GpuVbd, MatchesTheCpuWithoutAcceleration) {
  Model m = hanging_cloth();
  m.fields.air_drag = 0.5;  // drag's diagonal term too
  expect_parity(m, vbd(1.0 / 60, 6, 0, "cpu"), 20, "hanging cloth, no acceleration, drag");
}

// The flag in gusty wind: wind faces taken at the step's start on both (f_ext). Six steps of
// 1/120 s: from the seventh the top edge, compressed by the wind, buckles, and there the runs
// part by more than the bound for a few steps (docs/gpu.md, "Implicit Euler by vertex block
// descent on the GPU", has the measurements).
TEST_F(GpuVbd, MatchesTheCpuOnAFlagInWind) {
  const Scene s = test::example_scene("flag_in_wind");
  expect_parity(s.model, vbd(1.0 / 120, 10, 0.9, "cpu"), 6, "flag in wind");
}

// Step by step through the flag's buckling: each GPU step starts from the CPU's state (x, v and
// the guess's memory: the CPU hands the run over) and stays within one step's bound of the CPU's
// step, for 16 steps of 1/120 s, the buckling included. So where whole runs part (above), the
// GPU's steps are as accurate as elsewhere: the trajectory amplifies their float roundings.
TEST_F(GpuVbd, EachStepMatchesTheCpuThroughTheFlagsBuckling) {
  const Scene s = test::example_scene("flag_in_wind");
  const SimulationSettings c = vbd(1.0 / 120, 10, 0.9, "cpu");
  SimulationSettings g = c;
  g.backend = "gpu";
  Simulator cpu(s.model, c), gpu(s.model, g);
  double worst = 0, bound = 0;
  for (int k = 0; k < 16; ++k) {
    gpu.restore(cpu.state(), 0);
    ASSERT_TRUE(cpu.step());
    ASSERT_TRUE(gpu.step());
    const auto xc = positions(cpu);
    worst = std::max(worst, test::max_distance(xc, positions(gpu)));
    bound = float_bound(xc, 1, c.implicit.iterations);
    EXPECT_LE(test::max_distance(xc, positions(gpu)), bound) << "step " << k;
  }
  std::printf("flag in wind, one step at a time: GPU - CPU at most %.3g m (bound %.3g m)\n", worst,
              bound);
}

// Driven points (a pole shaken up and down) move along their path and are never solved for; the
// cloth follows them as on the CPU. Eight steps: as the flag in wind, the flag then goes through
// a few steps where the runs part by more than the bound (docs/gpu.md).
TEST_F(GpuVbd, MatchesTheCpuWithDrivenPoints) {
  const Scene s = test::example_scene("shaken_flag");
  ASSERT_FALSE(s.model.drives.empty());
  expect_parity(s.model, vbd(1.0 / 120, 10, 0.9, "cpu"), 8, "shaken flag");
}

// Conditional links (a lattice cube on a conditional floor, contacts made from the first steps):
// the GPU colours them as if always active, the CPU those near contact each step; the floor's
// points are fixed, so neither constrains the colours and the sweeps visit the same order.
TEST_F(GpuVbd, MatchesTheCpuWithConditionalLinks) {
  const Scene s = test::example_scene(
      "jelly_cube_bounce", {"lattice[0].origin=[-0.25,0.06,-0.25]", "contact[0].method=\"links\""});
  expect_parity(s.model, vbd(1.0 / 240, 10, 0.9, "cpu"), 10, "conditional floor");
}

// At rest the step's fixed point is the static equilibrium: the GPU's cloth comes to rest where
// the CPU's does (within 1 % of the sag; the CPU test ties that sag to leapfrog's).
TEST_F(GpuVbd, HangingClothRestsAtTheCpusStaticSag) {
  Model m = hanging_cloth();
  m.fields.air_drag = 6;
  const std::uint64_t steps = 2 * 60;
  Simulator cpu(m, vbd(1.0 / 60, 20, 0.9, "cpu")), gpu(m, vbd(1.0 / 60, 20, 0.9, "gpu"));
  ASSERT_TRUE(cpu.run_steps(steps));
  ASSERT_TRUE(gpu.run_steps(steps));
  double sag = 0;
  for (std::size_t i = 0; i < m.points.size(); ++i)
    sag = std::max(sag, double(m.points.initial_position[i].y - cpu.state().x()[i].y));
  EXPECT_GT(sag, 1e-3);
  EXPECT_LT(gpu.energies().kinetic, 1e-6);
  EXPECT_LT(test::max_distance(positions(gpu), positions(cpu)), 0.01 * sag) << "sag " << sag;
}

// solver_residual and solver_iterations, as the CPU reports them (sampled every step).
TEST_F(GpuVbd, ReportsTheCpusSolverColumns) {
  const Model m = hanging_cloth();
  auto column = [](const Simulator& sim, const std::string& name) {
    for (const auto& c : sim.profile().counters())
      if (c.name == name) return double(c.last);
    for (const auto& g : sim.profile().gauges())
      if (g.name == name) return g.last;
    return -1.0;
  };
  SimulationSettings c = vbd(1.0 / 60, 4, 0.9, "cpu"), g = c;
  g.backend = "gpu";
  c.sample_every = g.sample_every = 1;
  Simulator cpu(m, c), gpu(m, g);
  ASSERT_TRUE(cpu.run_steps(5));
  ASSERT_TRUE(gpu.run_steps(5));
  for (const char* name : {"solver_iterations", "vbd_colours", "vbd_acceleration_resets"})
    EXPECT_EQ(column(gpu, name), column(cpu, name)) << name;
  // Unconverged after 4 sweeps, the residual is several m g. g is Lipschitz in x with the
  // largest block, m/h^2 + the stiffnesses of a point's links (at most 4 structural, 4 shear
  // and 4 bending: FlagParams' defaults), so the GPU's positions, within the float bound of the
  // CPU's, give a residual within that block times the bound, over m g.
  const FlagParams p;
  const double mass = double(p.mass) / (12.0 * 12.0), h = c.step;
  const double block =
      mass / (h * h) + 4 * double(p.material.stiffness + p.shear_stiffness + p.bending_stiffness);
  const double tolerance =
      block * float_bound(positions(cpu), 5, c.implicit.iterations) / (mass * 9.81);
  const double rc = column(cpu, "solver_residual"), rg = column(gpu, "solver_residual");
  std::printf("residual: CPU %.6g, GPU %.6g (tolerance %.3g)\n", rc, rg, tolerance);
  EXPECT_GT(rc, 0.0);
  EXPECT_NEAR(rg, rc, tolerance);
}

TEST_F(GpuVbd, SameResultTwice) {
  const Model m = hanging_cloth();
  Simulator a(m, vbd(1.0 / 60, 10, 0.9, "gpu")), b(m, vbd(1.0 / 60, 10, 0.9, "gpu"));
  ASSERT_TRUE(a.run_steps(15));
  ASSERT_TRUE(b.run_steps(15));
  EXPECT_EQ(state_hash(a.state()), state_hash(b.state()));
}

// The state (x, v and the guess's memory) is all the solver keeps between steps: a run resumed
// from a checkpoint of the GPU's state goes on bit for bit; a CPU run hands over its memory.
TEST_F(GpuVbd, ResumeFromACheckpointIsBitIdentical) {
  const Model m = hanging_cloth();
  const SimulationSettings s = vbd(1.0 / 60, 10, 0.9, "gpu");
  Simulator whole(m, s), first(m, s);
  ASSERT_TRUE(whole.run_steps(12));
  ASSERT_TRUE(first.run_steps(6));
  const State checkpoint = first.state();
  ASSERT_EQ(checkpoint.stage_memory.size(), 1u);  // the guess's memory came back from the device
  Simulator resumed(m, s);
  resumed.restore(checkpoint, 0);
  ASSERT_TRUE(resumed.run_steps(6));
  EXPECT_EQ(state_hash(resumed.state()), state_hash(whole.state()));
}

// The other way: the CPU takes over a GPU run from its downloaded state (x, v and the guess's
// memory in float) and ends within the float bound of a run on the CPU throughout.
TEST_F(GpuVbd, TheCpuTakesOverAGpuRun) {
  const Model m = hanging_cloth();
  Simulator gpu(m, vbd(1.0 / 60, 10, 0.9, "gpu")), whole(m, vbd(1.0 / 60, 10, 0.9, "cpu"));
  ASSERT_TRUE(gpu.run_steps(6));
  ASSERT_TRUE(whole.run_steps(12));
  Simulator cpu(m, vbd(1.0 / 60, 10, 0.9, "cpu"));
  cpu.restore(gpu.state(), 0);
  ASSERT_EQ(cpu.state().stage_memory.size(), 1u);
  ASSERT_TRUE(cpu.run_steps(6));
  const double off = test::max_distance(positions(cpu), positions(whole));
  std::printf("GPU 6 steps then CPU 6: %.3g m from the CPU's 12\n", off);
  EXPECT_LE(off, float_bound(positions(whole), 12, 10));
}

TEST_F(GpuVbd, RefusesOtherSolversByName) {
  for (const char* solver : {"matrix_free", "eigen"}) {
    SimulationSettings s = vbd(1.0 / 60, 10, 0.9, "gpu");
    s.implicit.solver = *parse_name<ImplicitSolver>(solver);
    try {
      Simulator sim(hanging_cloth(), s);
      ADD_FAILURE() << solver << " ran on the GPU";
    } catch (const std::invalid_argument& e) {
      EXPECT_NE(std::string(e.what()).find(std::string("implicit solver '") + solver +
                                           "' has no GPU version"),
                std::string::npos)
          << e.what();
    }
  }
}

TEST_F(GpuVbd, RefusesTheCoarseCorrectionByName) {
  SimulationSettings s = vbd(1.0 / 60, 10, 0.9, "gpu");
  s.implicit.coarse = VbdCoarse::aggregates;  // the default
  try {
    Simulator sim(hanging_cloth(), s);
    ADD_FAILURE() << "the coarse correction ran on the GPU";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("coarse correction (coarse = \"aggregates\""),
              std::string::npos)
        << e.what();
  }
}

// Geometric obstacles enter the GPU's solve (test_gpu_vbd_obstacles.cpp); an obstacle by facets
// does not, and is refused by name.
TEST_F(GpuVbd, RefusesAFacetObstacleByName) {
  Scene scene = test::example_scene("sphere_by_facets");
  scene.settings.integrator = "implicit_euler";
  scene.settings.implicit.solver = ImplicitSolver::vbd;
  scene.settings.implicit.coarse = VbdCoarse::off;
  scene.settings.backend = "gpu";
  try {
    Simulator sim(scene.model, scene.settings);
    ADD_FAILURE() << "vbd ran with a facet obstacle on the GPU";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("stage 'obstacle:ball' has no implicit terms on the GPU"),
              std::string::npos)
        << e.what();
  }
}

// A clique of 66 points (every pair linked) needs 66 colours: more dispatches per sweep than the
// GPU's VBD takes, refused by name with the count.
TEST_F(GpuVbd, RefusesAModelOfTooManyColours) {
  Model m;
  const std::uint32_t n = 66;
  for (std::uint32_t i = 0; i < n; ++i)
    m.points.add(PointKind::free, Real(0.01), {Real(i) * Real(0.01), 0, 0});
  for (std::uint32_t a = 0; a < n; ++a)
    for (std::uint32_t b = a + 1; b < n; ++b) m.links.pool<Spring>().add({a, b}, {1, 1});
  try {
    Simulator sim(m, vbd(1.0 / 60, 10, 0.9, "gpu"));
    ADD_FAILURE() << "66 colours ran on the GPU";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("need 66 colours"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace maille
