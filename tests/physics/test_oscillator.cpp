// A mass on a spring, against the analytic oscillator and against leapfrog's own theory.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "test_support.hpp"

namespace maille {
namespace {

constexpr double kPi = std::numbers::pi;

// Period against 2 pi sqrt(m/k). Leapfrog's discrete frequency is exactly
// omega_h = (2/h) asin(omega h / 2), so the measured period must match 2 pi / omega_h to the
// accuracy of locating zero crossings (linear interpolation, error O(h^2 omega^2) per crossing,
// averaged over 50 periods: 1e-7 relative), and its error against 2 pi sqrt(m/k) must shrink
// 4x when h halves.
TEST(Oscillator, LeapfrogPeriodMatchesTheoryAndConvergesAsHSquared) {
  const double m = 0.5, k = 200, L = 1, A = 0.1;
  const double omega = std::sqrt(k / m), T = 2 * kPi / omega;
  double err[2];
  const double steps[2] = {2e-3, 1e-3};
  for (int i = 0; i < 2; ++i) {
    const double h = steps[i];
    Simulator sim(test::oscillator(m, k, 0, L, A), test::settings(h));
    const auto c = test::upward_crossings(sim, 1, L, static_cast<std::uint64_t>(50.5 * T / h));
    ASSERT_GE(c.size(), 50u);
    const double measured = test::mean_period(c);
    const double discrete = 2 * kPi / ((2 / h) * std::asin(omega * h / 2));
    EXPECT_NEAR(measured / discrete, 1.0, 1e-6) << "h = " << h;
    err[i] = std::abs(measured - T) / T;
  }
  EXPECT_LT(err[0], 1e-3);
  EXPECT_NEAR(err[0] / err[1], 4.0, 0.2);  // second order
}

// Symplectic Euler has the same recurrence, hence the same period (it differs in velocities).
TEST(Oscillator, SymplecticEulerPeriod) {
  const double m = 0.5, k = 200, L = 1, A = 0.1, h = 1e-3;
  const double omega = std::sqrt(k / m);
  Simulator sim(test::oscillator(m, k, 0, L, A), test::settings(h, "symplectic_euler"));
  const auto c =
      test::upward_crossings(sim, 1, L, static_cast<std::uint64_t>(20.5 * 2 * kPi / omega / h));
  const double discrete = 2 * kPi / ((2 / h) * std::asin(omega * h / 2));
  EXPECT_NEAR(test::mean_period(c) / discrete, 1.0, 1e-6);
}

// Damping: u'' = -(k/m) u - (z/m) u' decays as exp(-z t / 2m). Peaks one period apart shrink by
// exp(-z T_d / 2m). Leapfrog feeds the damper the half-step-old velocity, which shifts the rate
// by O(h z/m) relative: with h z / m = 2e-5, a 0.5% tolerance is generous yet catches a wrong
// factor of 2 or a missing damper.
TEST(Oscillator, DamperDecayRate) {
  const double m = 0.5, k = 200, z = 0.4, L = 1, A = 0.1, h = 1e-4;
  Simulator sim(test::oscillator(m, k, z, L, A), test::settings(h));
  std::vector<double> peaks, times;
  double u_prev2 = 0, u_prev = sim.state().x()[1].x - L;
  for (int i = 0; i < 60000; ++i) {
    sim.step();
    const double u = sim.state().x()[1].x - L;
    if (i > 1 && u_prev > u_prev2 && u_prev >= u && u_prev > 0) {
      peaks.push_back(u_prev);
      times.push_back(sim.state().time - h);
    }
    u_prev2 = u_prev;
    u_prev = u;
  }
  ASSERT_GE(peaks.size(), 10u);
  const double rate = std::log(peaks[1] / peaks[9]) / (times[9] - times[1]);
  EXPECT_NEAR(rate / (z / (2 * m)), 1.0, 5e-3);
}

// Free fall is integrated exactly by leapfrog (constant acceleration), and by symplectic Euler
// along its own recurrence x_n = x_0 + n h v_0 + h^2 g n(n+1)/2. Only rounding separates them.
TEST(FreeFall, MatchesEachSchemesExactRecurrence) {
  for (const char* scheme : {"leapfrog", "symplectic_euler"}) {
    Model model;
    const Vec3 v0{1, 2, 0};
    model.points.add(PointKind::free, 2, {0, 10, 0}, v0);
    const double h = 1e-3;
    Simulator sim(std::move(model), test::settings(h, scheme));
    const int n = 2000;
    sim.run_steps(n);
    const double g = -9.81;
    const double expected_y = std::string(scheme) == "leapfrog"
                                  ? 10 + n * h * 2 + 0.5 * g * (n * h) * (n * h)
                                  : 10 + n * h * 2 + h * h * g * n * (n + 1) / 2.0;
    EXPECT_NEAR(sim.state().x()[0].y, expected_y, 1e-11) << scheme;
    EXPECT_NEAR(sim.state().x()[0].x, n * h * 1.0, 1e-12) << scheme;
  }
}

// A spring pendulum (nonlinear, gravity) over 1e5 steps: the energy error of a symplectic
// scheme stays bounded, of order (omega h)^2, and does not drift. omega h = 0.02 here, so the
// oscillation is about 1e-4 relative; 1e-3 bounds it; the drift bound (mean of the last 1000
// samples against the first 1000) is ten times tighter.
TEST(Energy, LeapfrogBoundedOverHundredThousandSteps) {
  Model model;
  const auto anchor = model.points.add(PointKind::fixed, 1, {0, 0, 0});
  const auto bob = model.points.add(PointKind::free, 0.25, {0.8, -0.7, 0.2});
  model.links.pool<Spring>().add({anchor, bob}, {100, 1});
  SimulationSettings s = test::settings(1e-3);
  s.sample_every = 10;
  Simulator sim(std::move(model), s);
  std::vector<double> energy;
  sim.on_sample(
      [&](const EnergySample& e, const Profile&) { energy.push_back(e.energies.total()); });
  ASSERT_TRUE(sim.run_steps(100000));
  ASSERT_EQ(energy.size(), 10000u);
  const double e0 = energy.front();
  double worst = 0, first = 0, last = 0;
  for (std::size_t i = 0; i < energy.size(); ++i) {
    worst = std::max(worst, std::abs(energy[i] - e0) / std::abs(e0));
    if (i < 1000) first += energy[i] / 1000;
    if (i >= energy.size() - 1000) last += energy[i] / 1000;
  }
  EXPECT_LT(worst, 1e-3);
  EXPECT_LT(std::abs(last - first) / std::abs(e0), 1e-4);
}

// The stability estimate is exact for one mass on one spring (omega^2 = k/m): 2/omega.
// Just inside, the run stays bounded; just outside, it blows up and the report names the step,
// the spring kind and the limit.
TEST(Stability, EstimateExactForOneSpringAndBlowUpIsNamed) {
  const double m = 0.5, k = 200, omega = std::sqrt(k / m);
  Simulator probe(test::oscillator(m, k, 0, 1, 0.1), test::settings(1e-3));
  EXPECT_NEAR(probe.stability().max_step, 2 / omega, 1e-12);
  EXPECT_EQ(probe.stability().link_kind, "spring");

  Simulator inside(test::oscillator(m, k, 0, 1, 0.1), test::settings(0.98 * 2 / omega));
  EXPECT_TRUE(inside.run_steps(20000));
  EXPECT_LT(std::abs(inside.state().x()[1].x - 1), 0.2);

  Simulator outside(test::oscillator(m, k, 0, 1, 0.1), test::settings(1.05 * 2 / omega));
  {
    const test::FpTrapsOff blowing_up;  // the run overflows on purpose
    EXPECT_FALSE(outside.run_steps(100000));
  }
  ASSERT_TRUE(outside.blow_up().has_value());
  EXPECT_EQ(outside.blow_up()->module, "spring");
  // At 1.05x the limit the amplitude grows by ~1.9 per step (eigenvalue of the leapfrog map at
  // h omega = 2.1), so the energy passes 1000x its scale after ~6 steps; the per-step kinetic
  // bound catches it then rather than at the next sample.
  EXPECT_GT(outside.blow_up()->step, 3u);
  EXPECT_LT(outside.blow_up()->step, 12u);
  EXPECT_NE(outside.blow_up()->message.find("exceeds the leapfrog stability limit"),
            std::string::npos)
      << outside.blow_up()->message;
}

// With damping the limit shrinks to (sqrt(c^2 + 4 w^2) - c) / w^2 (Jury conditions of the
// kick-drift recurrence): check it by running just inside (the oscillation decays) and just
// outside (it grows until the runaway-energy check stops the run). A long rest length keeps the
// motion linear while it grows: with L short the mass would swing through the anchor and the
// spring's nonlinearity would saturate the growth into a bounded but wrong oscillation.
TEST(Stability, DampedLimitIsSharp) {
  const double m = 0.01, k = 100, z = 0.5, L = 100, A = 0.1;
  const double w2 = k / m, c = z / m;
  const double limit = (std::sqrt(c * c + 4 * w2) - c) / w2;
  Simulator probe(test::oscillator(m, k, z, L, A), test::settings(1e-4));
  EXPECT_NEAR(probe.stability().max_step, limit, 1e-12);
  SimulationSettings in = test::settings(0.99 * limit), out = test::settings(1.02 * limit);
  in.sample_every = out.sample_every = 10;
  Simulator inside(test::oscillator(m, k, z, L, A), in);
  EXPECT_TRUE(inside.run_steps(50000));
  EXPECT_LT(std::abs(inside.state().x()[1].x - L), A);
  Simulator outside(test::oscillator(m, k, z, L, A), out);
  {
    const test::FpTrapsOff blowing_up;  // the run grows without bound on purpose
    EXPECT_FALSE(outside.run_steps(50000));
  }
  ASSERT_TRUE(outside.blow_up().has_value());
  EXPECT_NE(outside.blow_up()->message.find("runaway energy"), std::string::npos)
      << outside.blow_up()->message;
  EXPECT_EQ(outside.blow_up()->module, "spring_damper");
}

}  // namespace
}  // namespace maille
