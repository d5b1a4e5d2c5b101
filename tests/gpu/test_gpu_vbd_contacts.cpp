// The contact set's point pairs inside the GPU's vertex block descent (src/gpu/gpu_vbd_contacts.*):
// self-collision with primitive = "points" and [[contact]] through the broad phase, found on
// the host at the step's start and uploaded, against the CPU's solver (coarse = "off", the same
// sweeps and acceleration): a cloth falling onto a net of points step by step (the
// tolerance of gpu_test_support.hpp's expect_each_step_matches), nothing through the net over a
// whole run, the static gaps of a stack at rest (k (s - d) = m g), the same bits on
// every run, and the refusals of what the device does not read.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "gpu/gpu_test_support.hpp"
#include "maille/intersections.hpp"
#include "maille/link_registry.hpp"
#include "maille/scene.hpp"
#include "maille/simulator.hpp"
#include "maille/stage_registry.hpp"

namespace maille {
namespace {

using GpuVbdContacts = test::GpuTest;
using test::expect_each_step_matches;
using test::positions;
using test::vbd_settings;

Scene parse(const std::string& text) {
  auto s = parse_scene(text, "pairs.toml", LinkKindRegistry::with_builtins(),
                       StageRegistry::with_builtins());
  if (!s) throw std::runtime_error(s.error().to_string());
  return std::move(s.value());
}

// A free 8 x 8 cloth, 0.6 m square, 8 cm above a 15 x 15 net 1 m square in the plane y = 0
// (spacing 7.1 cm) held by its edges (self-collision collides free points), with `contacts`
// making them collide at 6 cm.
Scene cloth_over_floor(const std::string& contacts) {
  return parse(
      "[fields]\ngravity = [0.0, -9.81, 0.0]\n"
      "[[net]]\nname = \"floor\"\norigin = [-0.5, 0.0, -0.5]\nwidth = 1.0\ndepth = 1.0\n"
      "resolution = [15, 15]\nmass = 1.0\nstiffness = 100.0\nfixed = \"edges\"\n"
      "[[flag]]\nname = \"cloth\"\norigin = [-0.3, 0.08, -0.3]\nalong = [1.0, 0.0, 0.0]\n"
      "up = [0.0, 0.0, 1.0]\nwidth = 0.6\nheight = 0.6\nresolution = [8, 8]\nmass = 0.1\n"
      "stiffness = 500.0\nshear_stiffness = 100.0\nbending_stiffness = 0.0\ndamping = 0.02\n"
      "fixed = \"none\"\n" +
      contacts);
}

const std::string kSelfCollision =
    "[self_collision]\ngroups = [\"cloth\", \"floor\"]\nprimitive = \"points\"\nradius = 0.06\n"
    "stiffness = 200.0\ndamping = 0.2\nfriction = 0.3\n";
const std::string kGroupContact =
    "[[contact]]\nbetween = [\"cloth\", \"floor\"]\nstiffness = 200.0\ndamping = 0.2\n"
    "threshold = 0.06\n";

// The fall onto the floor, the impact and the rest (with friction, lagged): 40 steps.
TEST_F(GpuVbdContacts, ClothOnAFloorOfPointsMatchesTheCpuStepByStep) {
  expect_each_step_matches(cloth_over_floor(kSelfCollision), 40, "self-collision (points)");
}

TEST_F(GpuVbdContacts, ClothOnAContactFloorMatchesTheCpuStepByStep) {
  expect_each_step_matches(cloth_over_floor(kGroupContact), 40, "[[contact]] (broad phase)");
}

// Over a whole second no cloth point goes through the net: each stays above the net point
// nearest to it across the plane (the contact radius holds it 6 cm above a net point, 3.3 cm
// above the middle of a cell), on the CPU and the GPU. The runs are chaotic through the impact
// (a point lands on one side of a net point or the other, and the acceleration's fallback is a
// decision on the sweeps' merit): the float storage alone moves the CPU's run by 1e-7 m here,
// but one sweep more or less per step moves it by 3 to 11 cm. The GPU's float solve is another
// iterate of the same steps (the step-by-step test above), so the yardstick is the latter: the
// GPU ends closer to the CPU's run than the CPU's own runs with 9 and 11 sweeps do (measured:
// 0.9 and 2.2 cm against at least 3.1 and 5.2 cm).
TEST_F(GpuVbdContacts, NothingGoesThroughTheNetOverAWholeRun) {
  for (const std::string& contacts : {kSelfCollision, kGroupContact}) {
    const Scene s = cloth_over_floor(contacts);
    const Group& net = *s.model.group("floor");
    const Group& cloth = *s.model.group("cloth");
    const SimulationSettings settings = vbd_settings(s, "cpu");
    Simulator cpu(s.model, settings), gpu(s.model, vbd_settings(s, "gpu"));
    ASSERT_TRUE(cpu.run_steps(60));
    ASSERT_TRUE(gpu.run_steps(60)) << gpu.blow_up()->message;
    double neighbours = 1e9;  // the CPU's distance to its runs of one sweep less and one more
    for (const int sweeps : {settings.implicit.iterations - 1, settings.implicit.iterations + 1}) {
      SimulationSettings other = settings;
      other.implicit.iterations = sweeps;
      Simulator sim(s.model, other);
      ASSERT_TRUE(sim.run_steps(60));
      neighbours = std::min(neighbours, test::max_distance(positions(cpu), positions(sim)));
    }
    const auto xc = positions(cpu), xg = positions(gpu);
    for (const auto& x : {xc, xg}) {
      double above = 1;  // the smallest height of a cloth point over its nearest net point
      for (std::uint32_t c = cloth.first; c < cloth.first + cloth.count; ++c) {
        double nearest = 1e9, height = 0;
        for (std::uint32_t f = net.first; f < net.first + net.count; ++f) {
          const double across = std::hypot(double(x[c].x - x[f].x), double(x[c].z - x[f].z));
          if (across < nearest) nearest = across, height = double(x[c].y - x[f].y);
        }
        above = std::min(above, height);
      }
      EXPECT_GT(above, 0.02) << contacts;
    }
    const double off = test::max_distance(xc, xg);
    std::printf(
        "cloth on a net, 60 steps of 1/60 s: GPU - CPU %.3g m, CPU with a sweep less or more "
        "%.3g m\n",
        off, neighbours);
    EXPECT_LT(off, neighbours) << contacts;
  }
}

// A stack at rest: a 20 g base on a fixed anchor ([[contact]], threshold 6 cm) and a 10 g bead
// on the base (self-collision, radius 6 cm), both k = 100 N/m. Implicit Euler's rest is the
// static equilibrium exactly: the base's gap is s - (m_base + m_bead) g / k, the bead's over the
// base s - m_bead g / k. The dampers (z = 0.5 N.s/m) settle the stack within the 2 s (decay
// rates 12.5 and 25 per second). Tolerance: 1 um, 1e-3 of the smaller depth, far above float's
// rounding of 12 cm (7e-9 m).
TEST_F(GpuVbdContacts, AStackRestsAtTheStaticGaps) {
  const Scene s = parse(
      "[fields]\ngravity = [0.0, -9.81, 0.0]\n"
      "[[mass]]\nname = \"base\"\nposition = [0.0, 0.1, 0.0]\nmass = 0.02\n"
      "[[mass]]\nname = \"bead\"\nposition = [0.0, 0.25, 0.0]\nmass = 0.01\n"
      "[[fixed]]\nname = \"anchor\"\nposition = [0.0, 0.0, 0.0]\n"
      "[[contact]]\nbetween = [\"base\", \"anchor\"]\nstiffness = 100.0\ndamping = 0.5\n"
      "threshold = 0.06\n"
      "[self_collision]\ngroups = [\"bead\", \"base\"]\nprimitive = \"points\"\n"
      "radius = 0.06\nstiffness = 100.0\ndamping = 0.5\n");
  const double g = 9.81, k = 100, gap = 0.06;
  const double base = gap - 0.03 * g / k, bead = base + gap - 0.01 * g / k;
  for (const std::string backend : {"cpu", "gpu"}) {
    Simulator sim(s.model, vbd_settings(s, backend));
    ASSERT_TRUE(sim.run_steps(120)) << backend;
    const auto x = positions(sim);
    EXPECT_NEAR(double(x[0].y), base, 1e-6) << backend;
    EXPECT_NEAR(double(x[1].y), bead, 1e-6) << backend;
    EXPECT_NEAR(std::hypot(double(x[1].x), double(x[1].z)), 0.0, 1e-9) << backend;
  }
}

// The colours follow the pairs and no two points of a colour share one: the sweeps are
// Gauss-Seidel without races, so two runs give the same bits.
TEST_F(GpuVbdContacts, SameResultTwice) {
  const Scene s = cloth_over_floor(kSelfCollision);
  Simulator a(s.model, vbd_settings(s, "gpu")), b(s.model, vbd_settings(s, "gpu"));
  ASSERT_TRUE(a.run_steps(30));
  ASSERT_TRUE(b.run_steps(30));
  EXPECT_EQ(positions(a), positions(b));
}

// A facet obstacle's contacts are not in the contact set's arrays the device reads: refused by
// name before the run.
TEST_F(GpuVbdContacts, AFacetObstacleIsRefusedByName) {
  const Scene s = cloth_over_floor(
      "[[obstacle]]\nname = \"ball\"\nshape = \"sphere\"\nmethod = \"facets\"\n"
      "scale = [0.2, 0.2, 0.2]\nposition = [0.0, -0.3, 0.0]\ncollides_with = [\"cloth\"]\n");
  try {
    Simulator sim(s.model, vbd_settings(s, "gpu"));
    ADD_FAILURE() << "accepted";
  } catch (const std::invalid_argument& e) {
    const std::string why = e.what();
    EXPECT_NE(why.find("stage 'obstacle:ball' has no implicit terms on the GPU"), std::string::npos)
        << why;
    EXPECT_NE(why.find("--backend cpu"), std::string::npos) << why;
  }
}

// Self-collision by triangles: an 8 x 8 cloth, 0.6 m square, dropped 5 cm onto a 10 x 10
// hammock 0.8 m square held by two opposite edges, both colliding (point-triangle and
// edge-edge contacts, radius 1 cm, friction 0.3).
Scene cloth_over_hammock() {
  return parse(
      "[fields]\ngravity = [0.0, -9.81, 0.0]\n"
      "[[flag]]\nname = \"hammock\"\norigin = [-0.4, 0.0, -0.4]\nalong = [1.0, 0.0, 0.0]\n"
      "up = [0.0, 0.0, 1.0]\nwidth = 0.8\nheight = 0.8\nresolution = [10, 10]\nmass = 0.2\n"
      "stiffness = 800.0\nshear_stiffness = 200.0\nbending_stiffness = 0.0\ndamping = 0.02\n"
      "fixed = \"ends\"\n"
      "[[flag]]\nname = \"cloth\"\norigin = [-0.3, 0.05, -0.3]\nalong = [1.0, 0.0, 0.0]\n"
      "up = [0.0, 0.0, 1.0]\nwidth = 0.6\nheight = 0.6\nresolution = [8, 8]\nmass = 0.1\n"
      "stiffness = 500.0\nshear_stiffness = 100.0\nbending_stiffness = 0.0\ndamping = 0.02\n"
      "fixed = \"none\"\n"
      "[self_collision]\ngroups = [\"cloth\", \"hammock\"]\nprimitive = \"triangles\"\n"
      "radius = 0.01\ntopological_radius = 0\nstiffness = 500.0\ndamping = 0.05\n"
      "friction = 0.3\n");
}

// At 1/240 s no point reaches its drift limit: each GPU step from the CPU's state is the CPU's
// to rounding (8 roundings per update and sweep of the largest coordinate) through the fall,
// the landing and the rest (0.6 s). At 1/60 s the landing takes points to their limits: the
// CPU searches again and lets them go on, the device holds them at their balls' edge for the
// rest of the step (gpu_vbd_contacts.hpp); the step is then another iterate of the same solve,
// within the allowance (twice the CPU's own distance to its converged step).
TEST_F(GpuVbdContacts, ClothOnAHammockByTrianglesMatchesTheCpuStepByStep) {
  EXPECT_EQ(
      expect_each_step_matches(cloth_over_hammock(), 144, "self-collision (triangles)", 1.0 / 240),
      0);
  expect_each_step_matches(cloth_over_hammock(), 40, "self-collision (triangles)");
}

// Intersection-free on the device: over a whole second of the fall, the landing and the rest,
// no pair of the model's triangles crosses (the exact test of include/maille/intersections.hpp,
// every fifth step), on the CPU and the GPU; and the cloth rests on the hammock (no point of
// it below the hammock's lowest point).
TEST_F(GpuVbdContacts, TheClothNeverCrossesTheHammock) {
  const Scene s = cloth_over_hammock();
  const Group& cloth = *s.model.group("cloth");
  const Group& hammock = *s.model.group("hammock");
  for (const std::string backend : {"cpu", "gpu"}) {
    Simulator sim(s.model, vbd_settings(s, backend));
    IntersectionCount crossings;
    std::size_t worst = 0;
    for (int k = 0; k < 60; ++k) {
      ASSERT_TRUE(sim.step()) << backend << " step " << k;
      if (k % 5 == 4)
        worst = std::max(worst, crossings.count(sim.state().x(), s.model.surface.triangles));
    }
    EXPECT_EQ(worst, 0u) << backend;
    const auto x = positions(sim);
    double lowest_hammock = 1, lowest_cloth = 1;
    for (std::uint32_t p = hammock.first; p < hammock.first + hammock.count; ++p)
      lowest_hammock = std::min(lowest_hammock, double(x[p].y));
    for (std::uint32_t p = cloth.first; p < cloth.first + cloth.count; ++p)
      lowest_cloth = std::min(lowest_cloth, double(x[p].y));
    EXPECT_GT(lowest_cloth, lowest_hammock) << backend;
    EXPECT_LT(lowest_hammock, -0.01) << backend;  // it sagged under the cloth: they met
  }
}

// The wrung strip (examples/wrung_cloth.toml: 48 x 24, held by its ends, one end turned half
// a turn per second, no gravity, self-collision by triangles 6 mm thick) at the example's
// 1/60 s, VBD on the GPU, for 2.5 s: the strip winds onto itself from 1.3 s on (about 600
// touching point-face and edge pairs at 2.3 s), and no pair of its triangles ever crosses
// (every tenth step). The whole 6 s: `maille run examples/wrung_cloth.toml --backend gpu --set
// simulation.implicit.coarse="off"`, intersecting_pairs 0 in every row (docs/gpu.md).
TEST_F(GpuVbdContacts, AWrungStripNeverCrossesItself) {
  const Scene s = test::example_scene("wrung_cloth");
  SimulationSettings settings = s.settings;
  settings.backend = "gpu";
  settings.implicit.coarse = VbdCoarse::off;
  settings.threads = 1;
  Simulator sim(s.model, settings);
  IntersectionCount crossings;
  std::size_t worst = 0, contacts = 0;
  for (int k = 0; k < 150; ++k) {
    ASSERT_TRUE(sim.step()) << "step " << k;
    if (k % 10 == 9)
      worst = std::max(worst, crossings.count(sim.state().x(), s.model.surface.triangles));
  }
  // It did wind onto itself: touching point-face and edge pairs, summed over the steps.
  for (const Profile::Counter& c : sim.profile().counters())
    if (c.name == "self_triangle_contacts" || c.name == "self_edge_contacts") contacts += c.total;
  EXPECT_EQ(worst, 0u);
  EXPECT_GT(contacts, 0u);
}

}  // namespace
}  // namespace maille
