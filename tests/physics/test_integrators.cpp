// The integrator family against theory: convergence orders, energy-drift ranking, stability
// limits, and implicit Euler on a stiff flag.
#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <numbers>

#include "maille/builders.hpp"
#include "test_support.hpp"

namespace maille {
namespace {

constexpr double kPi = std::numbers::pi;
const char* const kSchemes[] = {
    "explicit_euler", "symplectic_euler", "leapfrog", "velocity_verlet", "rk4", "implicit_euler"};

// Global position error at t = 1 s of an undamped mass on a spring, against L + A cos(omega t).
// omega = 5 rad/s: at t = 1 the phase (5 rad) is not a multiple of pi, so a phase error shows
// at first order (at a whole period it would show squared, doubling every measured order).
double error_at_one_second(const char* scheme, double h) {
  const double m = 0.5, k = m * 25, L = 1, A = 0.1;
  SimulationSettings s = test::settings(h, scheme);
  s.implicit.tolerance = 1e-13;  // the solver must not limit the measured order
  Simulator sim(test::oscillator(m, k, 0, L, A), s);
  EXPECT_TRUE(sim.run_steps(static_cast<std::uint64_t>(std::llround(1 / h))));
  return std::abs(sim.state().x()[1].x - (L + A * std::cos(5 * sim.state().time)));
}

// Orders from h = 1/200, 1/400, 1/800: log2 of successive error ratios, averaged. The bands
// (+-0.15 around 1 and 2, +-0.3 around 4) leave room for the next term of the error expansion
// at these steps while separating the orders cleanly.
TEST(Integrators, ConvergenceOrders) {
  const std::pair<const char*, double> expected[] = {
      {"explicit_euler", 1}, {"symplectic_euler", 1}, {"implicit_euler", 1},
      {"leapfrog", 2},       {"velocity_verlet", 2},  {"rk4", 4}};
  for (const auto& [scheme, order] : expected) {
    const double e1 = error_at_one_second(scheme, 1.0 / 200);
    const double e2 = error_at_one_second(scheme, 1.0 / 400);
    const double e3 = error_at_one_second(scheme, 1.0 / 800);
    const double measured = 0.5 * (std::log2(e1 / e2) + std::log2(e2 / e3));
    EXPECT_NEAR(measured, order, order == 4 ? 0.3 : 0.15)
        << scheme << " errors " << e1 << " " << e2 << " " << e3;
  }
}

// Energy over 50 periods at 50 steps per period, undamped: explicit Euler gains energy, implicit
// Euler loses it, the symplectic schemes keep it bounded (their oscillation is no larger in the
// last ten periods than in the first ten: no drift), and RK4 (not symplectic) loses a little.
// The ranking is what theory says.
TEST(Integrators, EnergyDriftRanksAsTheorySays) {
  const double m = 0.5, k = m * 4 * kPi * kPi, L = 1, A = 0.1, h = 1.0 / 50;
  std::map<std::string, double> ratio;
  for (const char* scheme : kSchemes) {
    SimulationSettings s = test::settings(h, scheme);
    s.sample_every = 1;
    s.runaway_factor = 1e30;  // let explicit Euler's growth be observed, not stopped
    Simulator sim(test::oscillator(m, k, 0, L, A), s);
    std::vector<double> e;
    sim.on_sample([&](const EnergySample& x, const Profile&) { e.push_back(x.energies.total()); });
    ASSERT_TRUE(sim.run_steps(2500)) << scheme;
    ratio[scheme] = e.back() / e.front();
    const std::string name = scheme;
    if (name == "symplectic_euler" || name == "leapfrog" || name == "velocity_verlet") {
      double first = 0, last = 0;
      for (std::size_t i = 0; i < 500; ++i) {
        first = std::max(first, std::abs(e[i] / e.front() - 1));
        last = std::max(last, std::abs(e[e.size() - 1 - i] / e.front() - 1));
      }
      EXPECT_LT(last, 1.05 * first + 1e-12) << scheme << ": energy error grows";
      EXPECT_LT(last, name == "symplectic_euler" ? 0.15 : 0.01) << scheme;
    }
  }
  EXPECT_GT(ratio["explicit_euler"], 2.0);
  EXPECT_LT(ratio["implicit_euler"], 0.5);
  EXPECT_LT(ratio["rk4"], 1.0);
  EXPECT_GT(ratio["rk4"], 0.95);
  EXPECT_GT(ratio["explicit_euler"], ratio["leapfrog"]);
  EXPECT_GT(ratio["rk4"], ratio["implicit_euler"]);
}

// Stability limits on the test equation against closed forms: explicit Euler c / w2 (and 0
// without damping), kick-drift 2/w undamped, RK4 2 sqrt(2) / w undamped, implicit none.
TEST(Integrators, StabilityLimitsMatchClosedForms) {
  const double w2 = 400, w = 20, c = 4;
  auto limit = [&](const char* scheme, double damping) {
    Model m = test::oscillator(1, w2, damping, 1, 0.1);
    Simulator sim(std::move(m), test::settings(1e-3, scheme));
    return double(sim.stability().max_step);
  };
  EXPECT_EQ(limit("explicit_euler", 0), 0);
  EXPECT_NEAR(limit("explicit_euler", c), c / w2, 1e-12);
  EXPECT_NEAR(limit("leapfrog", 0), 2 / w, 1e-12);
  EXPECT_NEAR(limit("velocity_verlet", 0), 2 / w, 1e-12);
  EXPECT_NEAR(limit("rk4", 0), 2 * std::sqrt(2.0) / w, 1e-9);
  EXPECT_TRUE(std::isinf(limit("implicit_euler", c)));
}

// Each explicit scheme run 10 % beyond its limit blows up and is reported; 10 % inside it is
// bounded.
TEST(Integrators, BlowUpDetectedBeyondEachLimit) {
  for (const char* scheme : {"explicit_euler", "leapfrog", "velocity_verlet", "rk4"}) {
    auto run = [&](double factor) {
      Model m = test::oscillator(1, 400, 4, 100, 0.1);
      Simulator probe(m, test::settings(1e-3, scheme));
      SimulationSettings s = test::settings(factor * probe.stability().max_step, scheme);
      s.sample_every = 10;
      Simulator sim(std::move(m), s);
      return sim.run_steps(20000);
    };
    EXPECT_TRUE(run(0.9)) << scheme;
    const test::FpTrapsOff blowing_up;  // beyond the limit, x overflows to inf on purpose
    EXPECT_FALSE(run(1.1)) << scheme;
  }
}

struct RewritingStage final : Stage {
  std::string name() const override { return "facet_responses"; }
  Phase phase() const override { return Phase::response; }
  void apply(const Model&, State&, const StageContext&) override {}
};

// A stage that rewrites state after the fact cannot be combined with schemes that evaluate
// forces at intermediate states: refused with a message naming both.
TEST(Integrators, IncompatibleStageIsRefused) {
  Simulator rk4(test::oscillator(1, 100, 0, 1, 0.1), test::settings(1e-3, "rk4"));
  try {
    rk4.add_stage(std::make_unique<RewritingStage>());
    FAIL() << "rk4 accepted a state-rewriting stage";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("facet_responses"), std::string::npos);
    EXPECT_NE(std::string(e.what()).find("rk4"), std::string::npos);
  }
  Simulator leapfrog(test::oscillator(1, 100, 0, 1, 0.1), test::settings(1e-3));
  EXPECT_NO_THROW(leapfrog.add_stage(std::make_unique<RewritingStage>()));
  // Implicit Euler runs it after its solve, on the solved motion (ResponseTiming::after_solve):
  // accepted, and velocity Verlet, which evaluates forces twice, refuses it.
  Simulator implicit(test::oscillator(1, 100, 0, 1, 0.1), test::settings(1e-3, "implicit_euler"));
  EXPECT_NO_THROW(implicit.add_stage(std::make_unique<RewritingStage>()));
  Simulator verlet(test::oscillator(1, 100, 0, 1, 0.1), test::settings(1e-3, "velocity_verlet"));
  EXPECT_THROW(verlet.add_stage(std::make_unique<RewritingStage>()), std::invalid_argument);
}

Model stiff_flag() {
  Model m;
  FlagParams p;
  p.nx = 12;
  p.ny = 8;
  p.width = 0.6;
  p.height = 0.4;
  p.mass = 2;
  p.material = {20000, 2};
  p.shear_stiffness = 10000;
  p.bending_stiffness = 2000;
  p.fixed = FlagFixed::pole;
  build_flag(m, p, "flag");
  m.fields.air_drag = 2;
  return m;
}

// Implicit Euler on a stiff flag at 100 times leapfrog's stable step stays stable and comes to
// rest at the static solution: the same as a long leapfrog run at half its limit. Both rest
// states satisfy f(x) = 0, so they must agree far better than the sag itself: within 1 % of it.
TEST(Integrators, ImplicitEulerStiffFlagRestsAtStaticSolution) {
  Simulator probe(stiff_flag(), test::settings(1e-4));
  const double h_lf = probe.stability().max_step;
  ASSERT_LT(h_lf, 1e-3);

  Simulator implicit(stiff_flag(), test::settings(100 * h_lf, "implicit_euler"));
  const auto implicit_steps = static_cast<std::uint64_t>(6.0 / (100 * h_lf));
  ASSERT_TRUE(implicit.run_steps(implicit_steps)) << implicit.blow_up()->message;

  Simulator leapfrog(stiff_flag(), test::settings(0.5 * h_lf));
  ASSERT_TRUE(leapfrog.run_steps(static_cast<std::uint64_t>(6.0 / (0.5 * h_lf))));

  EXPECT_LT(implicit.energies().kinetic, 1e-6);
  double worst = 0, sag = 0;
  for (std::size_t i = 0; i < implicit.state().size(); ++i) {
    worst = std::max(worst, double(norm(implicit.state().x()[i] - leapfrog.state().x()[i])));
    sag = std::max(
        sag, double(implicit.model().points.initial_position[i].y - implicit.state().x()[i].y));
  }
  EXPECT_GT(sag, 1e-3);  // it did sag under its weight
  EXPECT_LT(worst, 0.01 * sag) << "largest distance between the two rest states; sag " << sag;
}

// The matrix-free and the assembled (Eigen) solvers agree on a swinging flag.
TEST(Integrators, MatrixFreeAndEigenSolversAgree) {
  std::vector<Vec3> end[2];
  const ImplicitSolver solvers[2] = {ImplicitSolver::matrix_free, ImplicitSolver::eigen};
  for (int k = 0; k < 2; ++k) {
    SimulationSettings s = test::settings(2e-3, "implicit_euler");
    s.implicit.solver = solvers[k];
    s.implicit.tolerance = 1e-12;
    Model m = stiff_flag();
    m.fields.wind.velocity = {3, 0, 2};
    Simulator sim(std::move(m), s);
    ASSERT_TRUE(sim.run_steps(300));
    end[k].assign(sim.state().x().begin(), sim.state().x().end());
  }
  for (std::size_t i = 0; i < end[0].size(); ++i) EXPECT_LT(norm(end[0][i] - end[1][i]), 1e-8);
}

// Newton iterations converge to the backward-Euler solution of the nonlinear system: a mass
// swinging on a stretched spring (the force turns with the spring: nonlinear) with a large
// step. The iterations use the definite Jacobian (a compressed spring's negative transverse
// stiffness is clamped), so convergence is linear rather than quadratic when the spring
// compresses: the distance to the 10-iteration result must shrink from 1 to 2 to 4 iterations,
// and be far smaller at 4 than at 1 (plain Baraff-Witkin).
TEST(Integrators, NewtonIterationsConverge) {
  auto run = [](int newton) {
    Model m;
    m.fields.gravity = {0, -9.81, 0};
    const auto anchor = m.points.add(PointKind::fixed, 1, {0, 0, 0});
    const auto bob = m.points.add(PointKind::free, 1, {1.2, 0.5, 0});
    m.links.pool<Spring>().add({anchor, bob}, {400, 1});
    SimulationSettings s = test::settings(0.05, "implicit_euler");
    s.implicit.newton_iterations = newton;
    s.implicit.tolerance = 1e-12;
    Simulator sim(std::move(m), s);
    sim.run_steps(20);
    return sim.state().x()[1];
  };
  const Vec3 one = run(1), two = run(2), four = run(4), ten = run(10);
  EXPECT_GT(norm(one - ten), 1e-3);
  EXPECT_LT(norm(two - ten), norm(one - ten));
  EXPECT_LT(norm(four - ten), norm(two - ten));
  EXPECT_LT(norm(four - ten), 0.05 * norm(one - ten));
}

}  // namespace
}  // namespace maille
