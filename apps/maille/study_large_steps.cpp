// `maille study large-steps`: implicit Euler at animation steps (1/60 to 1/240 s) with every
// contact in the solve, against leapfrog at its own limit, on two cloths:
//
//   sphere  the peer harness's scene (bench/peer: a 1 m, 0.3 kg cloth, structural springs of
//           2000 N/m and shear of 500, dropped flat from 0.75 m onto a fixed geometric sphere
//           of radius 0.25 m), so that its rows sit beside Bullet's in the report
//   heap    a self-colliding cloth (0.8 m, 0.2 kg, 300 N/m) dropped edge-first on a plane with
//           friction: it folds onto itself (self-collision by a thin layer of particle-face
//           contacts: primitive = "triangles", radius a third of the spacing, no topological
//           exclusion; with radius = the spacing and the default exclusion, VBD at 1/60 s
//           with 10 sweeps crossed 544 triangle pairs at 32^2 and stretched 29 %)
//   drape   examples/cloth_on_sphere.toml (read from the file, `--examples`) at 64^2: a 1 m, 0.25
//   kg cloth (400 N/m, bending
//           2 N/m) dropped on a ball standing on the ground, with self-collision (the
//           example's thin layer: particle-face contacts 8 mm thick); the real-time
//           case, on two threads, VBD only (leapfrog at its limit with self-collision is
//           minutes), 3 s simulated: the fall, the drape and the folds settling
//
// Writes large_steps.csv:
//
//   scene,particles,solver,step_s,iterations,wall_s_per_sim_s,max_stretch,max_penetration_m,
//   final_kinetic_J,max_residual,stable,sim_s,coarse,threads
//
// solver: leapfrog (at 0.9 of the engine's stability estimate), matrix_free (Newton iterations in
// `iterations`, 0 for the default one) or vbd (sweeps in `iterations`); max_stretch over structural
// links and samples (every 1/240 s, or every step when longer); max_penetration from the obstacle's
// depth gauge at the same samples; max_residual the largest solver_residual (force imbalance over m
// g, implicit solvers); coarse: VBD's coarse correction (aggregates, or off: sweeps with the
// Chebyshev acceleration), empty for the other solvers. Only the steps are timed, on `threads`
// threads (one but for the drape).
// --quick: the sphere at 32^2, the heap at 24^2, six settings, 0.5 s simulated. The full study:
// the sphere at 32^2, 64^2, 128^2 and the heap at 32^2, 64^2 (at 128^2 leapfrog's limit makes it
// minutes), eleven settings (matrix_free with 3 Newton iterations at 32^2 only), 1 s; then the
// drape at 64^2 (four settings, 3 s).
#include <algorithm>
#include <cstdio>
#include <ostream>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "maille/clock.hpp"
#include "maille/scene.hpp"
#include "maille/simulator.hpp"
#include "study.hpp"

namespace maille::app {

namespace {

struct Setting {
  std::string solver;  // leapfrog, matrix_free, vbd
  double step = 0;     // s; 0: leapfrog's own (0.9 of the stability estimate)
  int iterations = 0;  // vbd: sweeps; matrix_free: Newton iterations (0: the default, 1)
  VbdCoarse coarse = VbdCoarse::aggregates;  // vbd: the coarse correction, or sweeps only
  int threads = 1;
};

std::string sphere_text(int n) {
  std::ostringstream t;
  t << "[fields]\ngravity = [0.0, -9.81, 0.0]\n"
    << "[[flag]]\nname = \"cloth\"\norigin = [-0.5, 0.75, -0.5]\nalong = [1.0, 0.0, 0.0]\n"
    << "up = [0.0, 0.0, 1.0]\nwidth = 1.0\nheight = 1.0\nresolution = [" << n << ", " << n
    << "]\nmass = 0.3\nstiffness = 2000.0\nshear_stiffness = 500.0\nbending_stiffness = 0.0\n"
    << "damping = 0.02\nfixed = \"none\"\n"
    << "[[obstacle]]\nname = \"ball\"\nshape = \"sphere\"\nmethod = \"geometric\"\n"
    << "scale = [0.25, 0.25, 0.25]\ncollides_with = [\"cloth\"]\n";
  return t.str();
}

std::string heap_text(int n) {
  const double spacing = 0.8 / (n - 1);
  std::ostringstream t;
  t << "[fields]\ngravity = [0.0, -9.81, 0.0]\nair_drag = 0.1\n"
    << "[[flag]]\nname = \"cloth\"\norigin = [-0.4, 0.08, 0.0]\nalong = [1.0, 0.0, 0.0]\n"
    << "up = [0.0, 1.0, 0.06]\nwidth = 0.8\nheight = 0.8\nresolution = [" << n << ", " << n
    << "]\nmass = 0.2\nstiffness = 300.0\nshear_stiffness = 100.0\nbending_stiffness = 6.0\n"
    << "damping = 0.02\nfixed = \"none\"\n"
    << "[[obstacle]]\nname = \"floor\"\nshape = \"plane\"\nmethod = \"geometric\"\n"
    << "position = [0.0, 0.06, 0.0]\nstiffness = 400.0\ndamping = 0.2\nfriction = 0.3\n"
    << "collides_with = [\"cloth\"]\n"
    << "[self_collision]\ngroups = [\"cloth\"]\nradius = " << spacing / 3
    << "\ntopological_radius = 0\nstiffness = 300.0\ndamping = 0.05\nprimitive = \"triangles\"\n";
  return t.str();
}

struct Outcome {
  bool stable = true;
  double wall_per_sim = 0, max_stretch = 0, max_penetration = 0, final_kinetic = 0,
         max_residual = 0, step = 0, sim_s = 0;
};

// A study scene: sphere and heap from their text, the drape from examples/cloth_on_sphere.toml
// with its resolution overridden (its [simulation] is replaced by each setting's).
Scene study_scene(const std::string& name, int n, const std::filesystem::path& examples) {
  Result<Scene> scene =
      name == "drape"
          ? load_scene(examples / "cloth_on_sphere.toml",
                       std::vector<std::string>{"flag[0].resolution=[" + std::to_string(n) + ", " +
                                                std::to_string(n) + "]"})
          : parse_scene(name == "sphere" ? sphere_text(n) : heap_text(n), "large_steps.toml",
                        LinkKindRegistry::with_builtins(), StageRegistry::with_builtins());
  if (!scene) throw std::runtime_error("study scene: " + scene.error().to_string());
  return std::move(scene.value());
}

Outcome run(Scene scene, double spacing, const Setting& set, double duration) {
  SimulationSettings s = scene.settings;
  s.threads = set.threads;
  s.publish_every = kNeverEvery;
  s.sample_every = kNeverEvery;
  s.integrator = set.solver == "leapfrog" ? "leapfrog" : "implicit_euler";
  if (set.solver != "leapfrog") {
    s.implicit.solver = *parse_name<ImplicitSolver>(set.solver);
    if (set.iterations > 0)
      (set.solver == "vbd" ? s.implicit.iterations : s.implicit.newton_iterations) = set.iterations;
    s.implicit.coarse = set.coarse;
  }
  s.step = set.step > 0 ? set.step : 1e-4;
  Outcome o;
  {
    Simulator probe(scene.model, s);
    if (set.step <= 0) s.step = 0.9 * double(probe.stability().max_step);
  }
  o.step = s.step;
  Simulator sim(std::move(scene.model), s);
  const auto per_sample = std::max<std::uint64_t>(1, std::uint64_t(1.0 / 240 / s.step));
  const auto steps = std::uint64_t(duration / s.step + 0.5);
  double wall = 0;
  for (std::uint64_t done = 0; o.stable && done < steps; done += per_sample) {
    const auto t0 = WallClock::now();
    o.stable = sim.run_steps(std::min(per_sample, steps - done));
    wall += seconds_since(t0);
    if (!o.stable) break;
    o.max_stretch = std::max(o.max_stretch, structural_stretch(sim, spacing));
    for (const auto& g : sim.profile().gauges()) {
      if (g.name.rfind("obstacle_", 0) == 0 && g.name.size() > 6 &&
          g.name.compare(g.name.size() - 6, 6, "_depth") == 0)
        o.max_penetration = std::max(o.max_penetration, g.last);
      if (g.name == "solver_residual") o.max_residual = std::max(o.max_residual, g.last);
    }
  }
  o.sim_s = sim.state().time;
  o.wall_per_sim = o.sim_s > 0 ? wall / o.sim_s : 0;
  if (o.stable) o.final_kinetic = sim.energies().kinetic;
  return o;
}

}  // namespace

void study_large_steps(const StudyOptions& o, const StudyWriter& write) {
  const double duration = o.quick ? 0.5 : 1.0;
  std::vector<Setting> settings;
  if (o.quick) {
    settings = {{"leapfrog", 0, 0},           {"matrix_free", 1.0 / 60, 0},
                {"matrix_free", 1.0 / 60, 3}, {"vbd", 1.0 / 60, 10},
                {"vbd", 1.0 / 240, 10},       {"vbd", 1.0 / 60, 10, VbdCoarse::off}};
  } else {
    settings.push_back({"leapfrog", 0, 0});
    for (const double h : {1.0 / 60, 1.0 / 120, 1.0 / 240})
      settings.push_back({"matrix_free", h, 0});
    settings.push_back({"matrix_free", 1.0 / 60, 3});
    for (const double h : {1.0 / 60, 1.0 / 120, 1.0 / 240}) settings.push_back({"vbd", h, 10});
    settings.push_back({"vbd", 1.0 / 60, 30});
    settings.push_back({"vbd", 1.0 / 60, 10, VbdCoarse::off});
    settings.push_back({"vbd", 1.0 / 240, 10, VbdCoarse::off});
  }
  // The real-time case: two threads at 1/60 s and at larger steps, fewer sweeps.
  const std::vector<Setting> drape_settings = {{"vbd", 1.0 / 60, 10, VbdCoarse::aggregates, 2},
                                               {"vbd", 1.0 / 30, 6, VbdCoarse::aggregates, 2},
                                               {"vbd", 1.0 / 20, 6, VbdCoarse::aggregates, 2},
                                               {"vbd", 1.0 / 20, 6, VbdCoarse::aggregates, 1}};
  struct Case {
    const char* scene;
    int n;
  };
  std::vector<Case> cases = {{"sphere", 32}, {"heap", 24}};
  if (!o.quick)
    cases = {{"sphere", 32}, {"sphere", 64}, {"sphere", 128},
             {"heap", 32},   {"heap", 64},   {"drape", 64}};
  std::printf("maille study large-steps -> %s (%.1f s simulated, one thread; the drape 3 s)\n",
              o.out.string().c_str(), duration);
  write("large_steps.csv", [&](std::ostream& out) {
    out << "scene,particles,solver,step_s,iterations,wall_s_per_sim_s,max_stretch,"
           "max_penetration_m,final_kinetic_J,max_residual,stable,sim_s,coarse,threads\n";
    for (const Case& c : cases) {
      const std::string scene = c.scene;
      const bool drape = scene == "drape";
      const double spacing = (scene == "heap" ? 0.8 : 1.0) / (c.n - 1);
      for (const Setting& set : drape ? drape_settings : settings) {
        // matrix_free with 3 Newton iterations only at 32^2: at 64^2 it took 398 s per simulated
        // second on the heap (measured), minutes of study for a row known to lose.
        if (set.solver == "matrix_free" && set.iterations > 1 && c.n > 32) continue;
        const Outcome r =
            run(study_scene(scene, c.n, o.examples), spacing, set, drape ? 3.0 : duration);
        const std::string coarse = set.solver == "vbd" ? std::string(to_string(set.coarse)) : "";
        out << c.scene << ',' << c.n * c.n << ',' << set.solver << ',' << r.step << ','
            << set.iterations << ',' << r.wall_per_sim << ',' << r.max_stretch << ','
            << r.max_penetration << ',' << r.final_kinetic << ',' << r.max_residual << ','
            << r.stable << ',' << r.sim_s << ',' << coarse << ',' << set.threads << '\n';
        std::printf(
            "  %-6s %6d %-11s %-10s h %-9.3g it %-3d thr %d %8.3f s/s stretch %6.3f pen %8.2e "
            "m%s\n",
            c.scene, c.n * c.n, set.solver.c_str(), coarse.c_str(), r.step, set.iterations,
            set.threads, r.wall_per_sim, r.max_stretch, r.max_penetration,
            r.stable ? "" : "  UNSTABLE");
      }
    }
  });
}

}  // namespace maille::app
