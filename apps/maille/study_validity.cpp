// `maille study validity`: the engine against closed-form physics, as one table (validity.csv):
// each case, the quantity, the analytic value, the measured one, the relative error and the
// tolerance the test suite holds it to. Leapfrog unless stated.
//
//   oscillator_period     T = 2 pi sqrt(m / k), mass on a spring, h = T / 200
//   convergence_order     error(h) / error(h / 2) of the period: 4 for a second-order scheme
//   damped_decay_rate     amplitude envelope exp(-z t / 2m) of a damped spring
//   string_mode_frequency first transverse mode of a stretched string of N beads:
//                         omega_1 = 2 sqrt(T / (m a)) sin(pi / (2 (N + 1)))
//   static_sag            a hanging mass (damped) rests m g / k below the spring's rest point
//   energy_drift          E(1e5 steps) / E(0), undamped oscillator at 200 steps a period
//                         (leapfrog's energy oscillates by (omega h)^2 / 8 ~ 1e-4 and does not
//                         drift)
#include <cmath>
#include <cstdio>
#include <numbers>
#include <ostream>
#include <vector>

#include "maille/links/spring.hpp"
#include "maille/links/spring_damper.hpp"
#include "maille/simulator.hpp"
#include "study.hpp"

namespace maille::app {

namespace {

constexpr double pi = std::numbers::pi;

SimulationSettings quiet(double h) {
  SimulationSettings s;
  s.step = h;
  s.publish_every = kNeverEvery;
  s.sample_every = kNeverEvery;
  s.threads = 1;
  return s;
}

Model spring_mass(double m, double k, double z, double amplitude, bool gravity) {
  Model model;
  model.fields.gravity = gravity ? Vec3{0, Real(-9.81), 0} : Vec3{0, 0, 0};
  const auto a = model.points.add(PointKind::fixed, 1, {0, 0, 0});
  const auto b = model.points.add(PointKind::free, Real(m), {Real(1 + amplitude), 0, 0});
  model.links.pool<SpringDamper>().add({a, b}, {Real(k), 1, Real(z)});
  return model;
}

// Mean period from upward zero crossings of x - 1 (linear interpolation between steps).
double measured_period(double h, double m, double k, int periods) {
  Simulator sim(spring_mass(m, k, 0, 0.01, false), quiet(h));
  std::vector<double> t;
  double prev = sim.state().x()[1].x - 1, prev_t = 0;
  while (int(t.size()) < periods + 1) {
    sim.step();
    const double u = sim.state().x()[1].x - 1, now = sim.state().time;
    if (prev < 0 && u >= 0) t.push_back(prev_t + (now - prev_t) * (-prev) / (u - prev));
    prev = u, prev_t = now;
  }
  return (t.back() - t.front()) / periods;
}

struct Row {
  const char* name;
  const char* quantity;
  double analytic, measured, tolerance;
};

}  // namespace

void study_validity(const StudyOptions& o, const StudyWriter& write) {
  std::printf("maille study validity -> %s\n", o.out.string().c_str());
  std::vector<Row> rows;
  const double m = 0.01, k = 40, T = 2 * pi * std::sqrt(m / k);
  rows.push_back({"oscillator_period", "period_s", T, measured_period(T / 200, m, k, 20), 1e-4});
  {
    const double e1 = std::abs(measured_period(T / 50, m, k, 10) - T);
    const double e2 = std::abs(measured_period(T / 100, m, k, 10) - T);
    rows.push_back({"convergence_order", "error_ratio_h_over_h2", 4, e1 / e2, 0.05});
  }
  {
    const double z = 0.004;  // N.s/m: decay rate z / 2m = 0.2 1/s
    Simulator sim(spring_mass(m, k, z, 0.01, false), quiet(T / 400));
    double first = 0, last = 0, t_first = 0, t_last = 0, prev = 0, prev2 = 0;
    for (int i = 0; i < 400 * 40; ++i) {  // 40 periods: peaks of x - 1
      sim.step();
      const double u = sim.state().x()[1].x - 1;
      if (i > 2 && prev > prev2 && prev >= u) {
        if (first == 0) first = prev, t_first = sim.state().time;
        last = prev, t_last = sim.state().time;
      }
      prev2 = prev, prev = u;
    }
    rows.push_back({"damped_decay_rate", "rate_per_s", z / (2 * m),
                    std::log(first / last) / (t_last - t_first), 2e-3});
  }
  {
    const int n = 15;
    const double a = 0.1, rest = 0.08, ks = 200, mb = 0.005, tension = ks * (a - rest);
    Model model;
    model.fields.gravity = {0, 0, 0};
    std::vector<std::uint32_t> id;
    for (int i = 0; i <= n + 1; ++i) {
      const bool end = i == 0 || i == n + 1;
      const double y = end ? 0 : 1e-5 * std::sin(pi * i / (n + 1));
      id.push_back(model.points.add(end ? PointKind::fixed : PointKind::free, Real(mb),
                                    {Real(a * i), Real(y), 0}));
    }
    for (int i = 0; i <= n; ++i)
      model.links.pool<Spring>().add({id[std::size_t(i)], id[std::size_t(i) + 1]},
                                     {Real(ks), Real(rest)});
    const double omega = 2 * std::sqrt(tension / (mb * a)) * std::sin(pi / (2 * (n + 1)));
    const double period = 2 * pi / omega;
    Simulator sim(std::move(model), quiet(period / 2000));
    const std::uint32_t mid = id[std::size_t(n / 2 + 1)];
    std::vector<double> t;
    double prev = sim.state().x()[mid].y, prev_t = 0;
    while (t.size() < 6) {
      sim.step();
      const double u = sim.state().x()[mid].y, now = sim.state().time;
      if (prev < 0 && u >= 0) t.push_back(prev_t + (now - prev_t) * (-prev) / (u - prev));
      prev = u, prev_t = now;
    }
    rows.push_back({"string_mode_frequency", "omega_rad_per_s", omega,
                    2 * pi / ((t.back() - t.front()) / 5), 1e-4});
  }
  {
    Model model;  // a vertical spring: anchor at the origin, the mass 1 m below at rest length
    const auto a = model.points.add(PointKind::fixed, 1, {0, 0, 0});
    const auto b = model.points.add(PointKind::free, Real(m), {0, -1, 0});
    model.links.pool<SpringDamper>().add({a, b}, {Real(k), 1, Real(0.05)});
    Simulator sim(std::move(model), quiet(T / 200));
    sim.run_steps(200 * 200);
    rows.push_back({"static_sag", "sag_m", m * 9.81 / k, -double(sim.state().x()[1].y) - 1, 1e-9});
  }
  {
    Simulator sim(spring_mass(m, k, 0, 0.01, false), quiet(T / 200));
    const double e0 = sim.energies().total();
    sim.run_steps(100000);
    rows.push_back({"energy_drift", "relative_energy", 1, sim.energies().total() / e0, 1e-3});
  }
  write("validity.csv", [&](std::ostream& f) {
    f << "case,quantity,analytic,measured,relative_error,tolerance\n";
    for (const Row& r : rows) {
      const double err = std::abs(r.measured - r.analytic) / std::abs(r.analytic);
      f << r.name << ',' << r.quantity << ',' << r.analytic << ',' << r.measured << ',' << err
        << ',' << r.tolerance << '\n';
      std::printf("  %-22s %-22s analytic %-12.6g measured %-12.6g error %.2e (tolerance %.0e)\n",
                  r.name, r.quantity, r.analytic, r.measured, err, r.tolerance);
    }
  });
}

}  // namespace maille::app
