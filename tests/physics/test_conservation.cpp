// Invariants of internal forces: momentum, angular momentum, zero force at rest, invariance under
// rigid rotation.
#include <gtest/gtest.h>

#include <random>

#include "maille/builders.hpp"
#include "test_support.hpp"

namespace maille {
namespace {

Model spinning_ball() {
  Model m;
  m.fields.gravity = {0, 0, 0};
  LatticeParams p;
  p.resolution = {5, 5, 5};
  p.shape = LatticeShape::ball;
  p.mass = 2;
  p.material = {500, 0.5};
  p.shear_stiffness = 250;
  build_lattice(m, p, "ball");
  // Random velocities plus a spin: every link is stretched and damped from the first step.
  std::mt19937 rng(7);
  std::uniform_real_distribution<Real> u(-1, 1);
  for (std::uint32_t i = 0; i < m.points.size(); ++i) {
    const Vec3 r = m.points.initial_position[i] - Vec3{0.5, 0.5, 0.5};
    m.points.initial_velocity[i] = cross(Vec3{0, 3, 1}, r) + Vec3{u(rng), u(rng), u(rng)};
  }
  return m;
}

Vec3 angular_momentum(const Model& m, const State& s) {
  Vec3 l{};
  for (std::uint32_t i = 0; i < m.points.size(); ++i)
    l += cross(s.x()[i], s.v()[i]) * m.points.mass[i];
  return l;
}

// Links act in equal and opposite pairs, so total momentum changes only by rounding: over 2000
// steps of a ball with springs and dampers, 1e-12 relative to the momentum scale sum m |v|.
TEST(Conservation, MomentumWithInternalLinksOnly) {
  Simulator sim(spinning_ball(), test::settings(1e-4));
  const Vec3 p0 = total_momentum(sim.model(), sim.state().v());
  double scale = 0;
  for (std::uint32_t i = 0; i < sim.model().points.size(); ++i)
    scale += sim.model().points.mass[i] * norm(sim.state().v()[i]);
  ASSERT_TRUE(sim.run_steps(2000));
  const Vec3 p1 = total_momentum(sim.model(), sim.state().v());
  EXPECT_LT(norm(p1 - p0), 1e-12 * scale);
}

// Spring-dampers are central (force along the link, dampers axial), so leapfrog conserves
// sum m x_{n+1} x v_{n+1/2} exactly up to rounding: x_{n+1} - x_n is parallel to v_{n+1/2} and
// sum x_n x f_n = 0 for central pairs. An isotropic damper would fail this test.
TEST(Conservation, AngularMomentumWithCentralLinks) {
  Simulator sim(spinning_ball(), test::settings(1e-4));
  sim.step();  // the state now holds x_1 and v_{1/2}
  const Vec3 l0 = angular_momentum(sim.model(), sim.state());
  ASSERT_TRUE(sim.run_steps(2000));
  const Vec3 l1 = angular_momentum(sim.model(), sim.state());
  EXPECT_LT(norm(l1 - l0), 1e-10 * norm(l0));
}

// A built model at rest with rest lengths taken from its geometry feels no link force.
TEST(Conservation, ZeroForceAtRest) {
  Model m;
  m.fields.gravity = {0, 0, 0};
  FlagParams p;
  p.nx = 9;
  p.ny = 7;
  build_flag(m, p, "flag");
  Simulator sim(std::move(m), test::settings(1e-4));
  sim.step();
  for (const Vec3& v : sim.state().v()) EXPECT_LT(norm(v), 1e-15);
}

// Rotating the whole model rotates the forces: compare one force pass on a deformed lattice
// with the same pass on its rigidly rotated copy.
TEST(Conservation, ForcesInvariantUnderRigidRotation) {
  auto forces = [](bool rotate) {
    Model m = spinning_ball();
    std::mt19937 rng(3);
    std::uniform_real_distribution<Real> u(-0.03, 0.03);
    const Real c = std::cos(Real(0.7)), s = std::sin(Real(0.7));
    auto rot = [&](const Vec3& v) {
      return rotate ? Vec3{c * v.x - s * v.y, s * v.x + c * v.y, v.z} : v;
    };
    for (std::uint32_t i = 0; i < m.points.size(); ++i) {
      m.points.initial_position[i] =
          rot(m.points.initial_position[i] + Vec3{u(rng), u(rng), u(rng)});
      m.points.initial_velocity[i] = rot(m.points.initial_velocity[i]);
    }
    SimulationSettings st = test::settings(1e-6);
    Simulator sim(std::move(m), st);
    sim.energies();  // one force pass into state.f
    return std::vector<Vec3>(sim.state().f().begin(), sim.state().f().end());
  };
  const auto f0 = forces(false);
  const auto f1 = forces(true);
  const Real c = std::cos(Real(0.7)), s = std::sin(Real(0.7));
  double scale = 0;
  for (const Vec3& f : f0) scale = std::max(scale, double(norm(f)));
  for (std::size_t i = 0; i < f0.size(); ++i) {
    const Vec3 r{c * f0[i].x - s * f0[i].y, s * f0[i].x + c * f0[i].y, f0[i].z};
    EXPECT_LT(norm(r - f1[i]), 1e-11 * scale) << "point " << i;
  }
}

}  // namespace
}  // namespace maille
