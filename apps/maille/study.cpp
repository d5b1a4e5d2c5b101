// `maille study integrators`: the stability, accuracy and cost study of the time-integration
// schemes, written as CSV files (one per question) and summarised on the terminal.
//
//   stability.csv  largest stable step against stiffness, per scheme (test-equation analysis)
//   accuracy.csv   global error at t = 1 s against the step, per scheme (mass on a spring)
//   energy.csv     energy after 50 periods / initial, per scheme (undamped, 50 steps a period)
//   cost.csv       wall time per step (median of five blocks of 40 steps) and force passes on a
//                  64 x 64 flag, per scheme
//   crossover.csv  wall time per simulated second of a hanging flag at each scheme's usable
//                  step, against stiffness, with the quality measures that decided it
//
// `maille study all` runs the four studies into OUT/<study>/ and writes OUT/durations.csv.
#include "study.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <limits>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "maille/builders.hpp"
#include "maille/clock.hpp"
#include "maille/exit_codes.hpp"
#include "maille/interrupt.hpp"
#include "maille/io.hpp"
#include "maille/links/spring.hpp"
#include "maille/simulator.hpp"

namespace maille::app {

namespace {

const char* const kSchemes[] = {
    "explicit_euler", "symplectic_euler", "leapfrog", "velocity_verlet", "rk4", "implicit_euler"};

SimulationSettings quiet(double h, const std::string& scheme) {
  SimulationSettings s;
  s.step = h;
  s.integrator = scheme;
  s.publish_every = kNeverEvery;
  s.sample_every = kNeverEvery;
  return s;
}

Model oscillator(double m, double k, double rest, double amplitude) {
  Model model;
  model.fields.gravity = {0, 0, 0};
  const auto anchor = model.points.add(PointKind::fixed, 1, {0, 0, 0});
  const auto bob = model.points.add(PointKind::free, Real(m), {Real(rest + amplitude), 0, 0});
  model.links.pool<Spring>().add({anchor, bob}, {Real(k), Real(rest)});
  return model;
}

// One mass of 1 g on a spring (a cloth particle), with and without a damper.
void stability(std::ostream& out) {
  out << "scheme,stiffness_N_per_m,mass_kg,damping_Ns_per_m,max_stable_step_s\n";
  for (const char* scheme : kSchemes) {
    const auto integrator = IntegratorRegistry::builtin().find(scheme)->make({});
    for (double z : {0.0, 0.01})
      for (double k = 10; k <= 1e6 * 1.001; k *= std::sqrt(10.0))
        out << scheme << ',' << k << ",0.001," << z << ','
            << integrator->stable_step(Real(k / 1e-3), Real(z / 1e-3)) << '\n';
  }
}

void accuracy(std::ostream& out) {
  out << "scheme,step_s,error_at_1s_m\n";
  for (const char* scheme : kSchemes)
    for (double h = 1.0 / 50; h >= 1.0 / 3200 * 0.999; h /= 2) {
      SimulationSettings s = quiet(h, scheme);
      s.implicit.tolerance = Real(1e-13);
      Simulator sim(oscillator(0.5, 12.5, 1, 0.1), s);  // omega = 5 rad/s
      sim.run_steps(static_cast<std::uint64_t>(std::llround(1 / h)));
      out << scheme << ',' << h << ','
          << std::abs(sim.state().x()[1].x - (1 + 0.1 * std::cos(5 * sim.state().time))) << '\n';
    }
}

void energy(std::ostream& out) {
  out << "scheme,periods,steps_per_period,energy_ratio\n";
  const double pi = 3.14159265358979323846, h = 1.0 / 50;
  for (const char* scheme : kSchemes) {
    SimulationSettings s = quiet(h, scheme);
    s.runaway_factor = 1e30;
    Simulator sim(oscillator(0.5, 0.5 * 4 * pi * pi, 1, 0.1), s);
    const double e0 = sim.energies().total();
    sim.run_steps(2500);
    out << scheme << ",50,50," << sim.energies().total() / e0 << '\n';
  }
}

Model study_flag(std::uint32_t nx, std::uint32_t ny, double stiffness) {
  Model m;
  FlagParams p;
  p.nx = nx;
  p.ny = ny;
  p.width = 1.5;
  p.height = 1;
  p.mass = 0.3;
  p.material = {Real(stiffness), Real(0.01)};
  p.shear_stiffness = Real(stiffness / 2);
  p.bending_stiffness = Real(stiffness / 10);
  build_flag(m, p, "flag");
  m.fields.air_drag = 0.5;
  return m;
}

// The crossover scene: the same flag hanging from its pole under gravity, released flat, with
// enough air drag (5 /s: e^-15 after three seconds) to settle, so that its final sag is the
// static one whatever the scheme.
Model hanging_flag(double stiffness) {
  Model m = study_flag(24, 16, stiffness);
  m.fields.air_drag = 5;
  return m;
}

void cost(std::ostream& out, int threads) {
  out << "scheme,points,threads,force_passes,ns_per_step,ns_per_particle_step,cg_iterations\n";
  for (const char* scheme : kSchemes) {
    Model m = study_flag(64, 64, 200);
    m.fields.wind.velocity = {4, 0, 2};
    SimulationSettings s = quiet(scheme == std::string("implicit_euler") ? 1e-3 : 2e-5, scheme);
    s.threads = threads;
    Simulator sim(std::move(m), s);
    sim.run_steps(3);
    // The median of five blocks of 40 steps: one block is tens of milliseconds, and on a shared
    // machine a single one can be taken twice as long by a neighbour.
    const int steps = 40;
    std::vector<double> block_ns;
    for (int b = 0; b < 5; ++b) {
      const auto t0 = WallClock::now();
      sim.run_steps(steps);
      block_ns.push_back(seconds_since(t0) * 1e9 / steps);
    }
    std::sort(block_ns.begin(), block_ns.end());
    const double ns = block_ns[block_ns.size() / 2];
    std::uint64_t cg = 0;
    for (const auto& c : sim.profile().counters())
      if (c.name == "cg_iterations") cg = c.last;
    out << scheme << ',' << sim.model().points.size() << ',' << sim.threads() << ','
        << sim.integrator().force_evaluations() << ',' << ns << ','
        << ns / sim.model().points.size() << ',' << cg << '\n';
  }
}

// Visual quality of the hanging flag: its sag (mean displacement of the free points once it
// has settled, at t = 3 s) and its largest structural stretch at any time of the run (sampled
// every 10 ms), i.e. where it hangs and how rubbery it looks while falling.
struct Quality {
  double sag = 0;
  double peak_stretch = 0;
};

double sag(const Simulator& sim) {
  const auto& pts = sim.model().points;
  double total = 0;
  std::size_t n = 0;
  for (std::uint32_t i = 0; i < pts.size(); ++i)
    if (pts.inv_mass[i] > 0) {
      total += norm(sim.state().x()[i] - pts.initial_position[i]);
      ++n;
    }
  return total / double(n);
}

struct Run {
  bool stable = false;
  double wall_per_simulated_second = 0;
  Quality q;
};

Run run_flag(double stiffness, const std::string& scheme, double h) {
  constexpr double duration = 3, sample = 0.01;
  Simulator sim(hanging_flag(stiffness), quiet(h, scheme));
  Run r;
  r.stable = true;
  double wall = 0;
  for (double t = 0; r.stable && t < duration - 1e-9; t += sample) {
    const auto steps = std::max<std::uint64_t>(1, std::llround(sample / h));
    const auto t0 = WallClock::now();
    r.stable = sim.run_steps(steps);
    wall += seconds_since(t0);  // quality sampling is not charged to the scheme
    if (r.stable) r.q.peak_stretch = std::max(r.q.peak_stretch, structural_stretch(sim, 1.5 / 23));
  }
  r.wall_per_simulated_second = wall / sim.state().time;
  if (r.stable) r.q.sag = sag(sim);
  return r;
}

// Comparable visual quality: the sag within 2 % of the reference's, and the peak stretch
// within 10 % of the reference's or within 0.1 % absolute stretch (1.5 mm over the 1.5 m flag:
// invisible; implicit Euler's numerical damping lowers the dynamic peak of a very stiff
// flag, whose stretch is then far below anything one can see).
bool comparable(const Quality& a, const Quality& ref) {
  const double stretch_gap = std::abs(a.peak_stretch - ref.peak_stretch);
  return std::abs(a.sag - ref.sag) <= 0.02 * ref.sag &&
         (stretch_gap <= 0.1 * ref.peak_stretch || stretch_gap <= 1e-3);
}

void crossover(std::ostream& out, bool quick) {
  out << "stiffness_N_per_m,scheme,step_s,leapfrog_limit_s,wall_s_per_simulated_s,sag_m,"
         "peak_stretch,reference_sag_m,reference_peak_stretch,comparable\n";
  std::vector<double> stiffnesses = {1e2, 1e3, 1e4, 3e4, 1e5};
  if (quick) stiffnesses = {1e2, 3e4};
  for (double k : stiffnesses) {
    Simulator probe(hanging_flag(k), quiet(1e-6, "leapfrog"));
    const double limit = probe.stability().max_step;
    const Run ref = run_flag(k, "leapfrog", 0.25 * limit);  // the reference: a quarter step
    // One row, its columns written in this one place; a scheme with no usable step
    // (r == nullptr) leaves its own columns empty.
    auto row = [&](const std::string& scheme, double h, const Run* r) {
      const bool ok = r && r->stable && comparable(r->q, ref.q);
      out << k << ',' << scheme << ',';
      if (r) out << h;
      out << ',' << limit << ',';
      if (r)
        out << r->wall_per_simulated_second << ',' << r->q.sag << ',' << r->q.peak_stretch;
      else
        out << ",,";
      out << ',' << ref.q.sag << ',' << ref.q.peak_stretch << ',' << ok << '\n';
      if (r)
        std::printf("  k = %-8g %-16s h = %-10.3g %8.3f s wall per simulated s%s\n", k,
                    scheme.c_str(), h, r->wall_per_simulated_second,
                    ok ? "" : "  (quality not comparable)");
    };
    // Explicit schemes at 90 % of their own limit.
    for (const char* scheme : {"leapfrog", "symplectic_euler", "velocity_verlet", "rk4"}) {
      Simulator p(hanging_flag(k), quiet(1e-6, scheme));
      const double h = 0.9 * p.stability().max_step;
      const Run r = run_flag(k, scheme, h);
      row(scheme, h, &r);
    }
    // Implicit Euler at its usable step: the largest of 1/30, 1/60, ... s whose quality is
    // comparable to the reference, searched down to leapfrog's limit (below it there is no
    // reason to use it).
    bool found = false;
    for (double h = 1.0 / 30; h >= limit && !found; h /= 2) {
      const Run r = run_flag(k, "implicit_euler", h);
      if (r.stable && comparable(r.q, ref.q)) {
        row("implicit_euler", h, &r);
        found = true;
      }
    }
    if (!found) {
      row("implicit_euler", 0, nullptr);  // the limit stays in leapfrog_limit_s
      std::printf("  k = %-8g implicit_euler   no step above leapfrog's limit keeps the quality\n",
                  k);
    }
  }
}

}  // namespace

namespace {

const char* const kStudies[] = {"validity", "integrators", "self-collision", "obstacles",
                                "large-steps"};

// Ctrl-C or SIGTERM: the studies' loops poll nothing, so the process ends at once (exit 130),
// after removing the temporary of the CSV being written (interrupt.hpp, at once): the files
// already written stay complete, and no NAME.tmp is left.
constexpr char kInterrupted[] = "interrupted: the CSV files written so far are complete\n";

// `maille study all`: every study into OUT/<study>/, in the order of the report, and the wall
// time of each into OUT/durations.csv (the report quotes them). Stops at the first failure.
int study_all(const StudyOptions& o) {
  std::vector<std::pair<std::string, double>> durations;
  for (const char* topic : kStudies) {
    StudyOptions one = o;
    one.topic = topic;
    one.out = o.out / topic;
    const auto t0 = WallClock::now();
    if (const int rc = study(one); rc != exit_code::ok) return rc;
    durations.emplace_back(topic, seconds_since(t0));
  }
  try {
    AtomicFile f(o.out / "durations.csv");
    f.stream().precision(4);
    f.stream() << "study,quick,wall_s\n";
    for (const auto& [topic, s] : durations)
      f.stream() << topic << ',' << o.quick << ',' << s << '\n';
    f.commit();
  } catch (const std::runtime_error& e) {
    std::cerr << "error: " << e.what() << '\n';
    return exit_code::output_error;
  }
  for (const auto& [topic, s] : durations) std::printf("  %-15s %8.1f s\n", topic.c_str(), s);
  return exit_code::ok;
}

}  // namespace

int study(const StudyOptions& o) {
  interrupt::at_once(kInterrupted);
  if (o.topic == "all") return study_all(o);
  if (o.topic != "integrators" && o.topic != "self-collision" && o.topic != "validity" &&
      o.topic != "obstacles" && o.topic != "large-steps") {
    std::cerr << "unknown study '" << o.topic
              << "' (known: integrators, self-collision, validity, obstacles, large-steps, all)\n";
    return exit_code::usage;
  }
  // Output errors (an unwritable or full directory) end the study with exit 4 and the cause.
  try {
    std::filesystem::create_directories(o.out);
    // Each CSV appears whole or not at all (written under a temporary name, then renamed).
    auto write = [&](const char* name, auto&& body) {
      AtomicFile f(o.out / name);
      f.stream().precision(8);
      body(f.stream());
      f.commit();
    };
    if (o.topic == "validity") {
      study_validity(o, [&](const char* name, const std::function<void(std::ostream&)>& body) {
        write(name, body);
      });
      return exit_code::ok;
    }
    if (o.topic == "obstacles") {
      study_obstacles(o, [&](const char* name, const std::function<void(std::ostream&)>& body) {
        write(name, body);
      });
      return exit_code::ok;
    }
    if (o.topic == "large-steps") {
      study_large_steps(o, [&](const char* name, const std::function<void(std::ostream&)>& body) {
        write(name, body);
      });
      return exit_code::ok;
    }
    if (o.topic == "self-collision") {
      study_self_collision(o,
                           [&](const char* name, const std::function<void(std::ostream&)>& body) {
                             write(name, body);
                           });
      return exit_code::ok;
    }
    std::printf("maille study integrators -> %s\n", o.out.string().c_str());
    write("stability.csv", [](std::ostream& f) { stability(f); });
    write("accuracy.csv", [](std::ostream& f) { accuracy(f); });
    write("energy.csv", [](std::ostream& f) { energy(f); });
    write("cost.csv", [&](std::ostream& f) { cost(f, o.threads); });
    std::printf("crossover (flag 24 x 16 hanging under gravity, 3 s simulated):\n");
    write("crossover.csv", [&](std::ostream& f) { crossover(f, o.quick); });
  } catch (const std::filesystem::filesystem_error& e) {
    std::cerr << "error: cannot write the study to " << o.out.string() << ": " << e.code().message()
              << '\n';
    return exit_code::output_error;
  } catch (const std::runtime_error& e) {
    std::cerr << "error: " << e.what() << '\n';
    return exit_code::output_error;
  }
  return exit_code::ok;
}

// The largest stretch of a cloth's structural spring-dampers (rest length within 0.1 % of the
// grid spacing), |x_b - x_a| / L0 - 1, at the simulator's state.
double structural_stretch(const Simulator& sim, double spacing) {
  const auto* pool = sim.model().links.find("spring_damper");
  double worst = 0;
  for (std::size_t l = 0; l < pool->size(); ++l) {
    const double rest = pool->param(l, 1);
    if (rest > spacing * 1.001) continue;  // structural links only
    const auto [a, b] = pool->ends(l);
    worst = std::max(worst, norm(sim.state().x()[b] - sim.state().x()[a]) / rest - 1);
  }
  return worst;
}

}  // namespace maille::app
