// `maille study self-collision`: the broad phases against brute force, the cell size against
// the tuner, and the two topological exclusions, on the crumpled cloth of builders.hpp; and the
// cost of self-collision in a whole scene (a 128^2 flag in gusty wind). CSV files:
//
//   scaling.csv    ns per particle per pass against particle count, per broad phase and
//                  thread count (brute force up to 64k particles)
//   cell_size.csv  fixed cell sizes (multiples of the radius): measured time beside the P n^2
//                  model; the tuner's choice marked
//   tuner.csv      the tuner's own log of its last tuning: each candidate cell size, its timed
//                  pass and the P n^2 model's prediction, the choice marked
//   exclusion.csv  none / matrix / signature: pairs tested, excluded, cells skipped, memory, time
//   memory.csv     exclusion memory at 64k and 1M particles against a dense bit matrix
//   flag_wind.csv  a 128^2 flag in gusty wind, ns per particle-step without and with
//                  self-collision
//   intersections.csv  every self-colliding example (examples/, `--examples`), as written and
//                  with its self-collision taken out: the most crossing pairs of triangles over
//                  the run (intersections.hpp, every 10 steps and at the end), when they first
//                  appear, and the wall time (quick: the first 0.25 s; else at most 6 s)
#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <ostream>
#include <string>
#include <vector>

#include "maille/builders.hpp"
#include "maille/clock.hpp"
#include "maille/intersections.hpp"
#include "maille/scene.hpp"
#include "maille/self_collision.hpp"
#include "maille/simulator.hpp"
#include "study.hpp"

namespace maille::app {

namespace {

struct Cloth {
  Model model;
  std::vector<Vec3> x, v, f;
  Real spacing = 0;
};

Cloth crumpled(std::uint32_t n) {
  Cloth c;
  CrumpledClothParams p;
  p.n = n;
  build_crumpled_cloth(c.model, p, "cloth");
  c.model.prepare();
  c.x.assign(c.model.points.initial_position.begin(), c.model.points.initial_position.end());
  c.v.assign(c.x.size(), Vec3{});
  c.f.assign(c.x.size(), Vec3{});
  c.spacing = p.size / Real(n - 1);
  return c;
}

// Median wall time of `repeat` passes, after one warm-up pass (buffers sized, cell tuned).
double median_ns(SelfCollisionEngine& e, Cloth& c, int threads, int repeat,
                 SelfCollisionStats* last = nullptr) {
  SelfCollisionStats st = e.apply(c.x.data(), c.v.data(), c.f.data(), threads);
  std::vector<double> t;
  for (int r = 0; r < repeat; ++r) {
    const auto t0 = WallClock::now();
    st = e.apply(c.x.data(), c.v.data(), c.f.data(), threads);
    t.push_back(seconds_since(t0) * 1e9);
  }
  std::sort(t.begin(), t.end());
  if (last) *last = st;
  return t[t.size() / 2];
}

void scaling(std::ostream& out, bool quick, int threads) {
  out << "side,particles,broad_phase,threads,ns_per_particle_pass,candidate_pairs,contacts,"
         "occupied_cells,cell_size_m\n";
  const std::vector<std::uint32_t> sides = quick ? std::vector<std::uint32_t>{32, 64, 128}
                                                 : std::vector<std::uint32_t>{64, 128, 256, 512};
  for (std::uint32_t n : sides) {
    Cloth c = crumpled(n);
    for (BroadPhase b :
         {BroadPhase::brute, BroadPhase::uniform, BroadPhase::hashed, BroadPhase::hierarchical}) {
      if (b == BroadPhase::brute && n > (quick ? 64u : 256u)) continue;
      for (int t : {1, threads}) {
        if (t == threads && threads == 1 && t != 1) continue;
        SelfCollisionSettings s;
        s.radius = c.spacing;
        s.broad_phase = b;
        SelfCollisionEngine e(c.model, s);
        SelfCollisionStats st;
        const int repeat = b == BroadPhase::brute ? 1 : 5;
        const double ns = median_ns(e, c, t, repeat, &st);
        std::fprintf(stderr, "  %-12s %4u^2 %d thread(s): %.0f ns per particle\n",
                     std::string(to_string(b)).c_str(), n, t, ns / double(n * n));
        out << n << ',' << n * n << ',' << to_string(b) << ',' << t << ',' << ns / double(n * n)
            << ',' << st.candidate_pairs << ',' << st.contacts << ',' << st.occupied_cells << ','
            << st.cell_size << '\n';
        if (threads == 1) break;
      }
    }
  }
}

// One row of cell_size's CSV: the grid's cells, particles per cell and the P n^2 model there.
void cell_size_row(std::ostream& out, BroadPhase b, std::uint32_t n, double factor,
                   const SelfCollisionStats& st, double ns, bool chosen) {
  const double per_cell = double(n * n) / std::max<double>(double(st.occupied_cells), 1);
  out << to_string(b) << ',' << n << ',' << factor << ',' << st.cell_size << ','
      << st.occupied_cells << ',' << per_cell << ','
      << double(st.occupied_cells) * per_cell * per_cell << ',' << ns << ',' << (chosen ? 1 : 0)
      << '\n';
}

// The grid broad phases' settings on the crumpled cloth: contact radius one spacing.
SelfCollisionSettings grid_settings(const Cloth& c, BroadPhase b) {
  SelfCollisionSettings s;
  s.radius = c.spacing;
  s.broad_phase = b;
  return s;
}

void cell_size(std::ostream& out, bool quick) {
  out << "broad_phase,side,cell_factor,cell_size_m,occupied_cells,particles_per_cell,"
         "model_P_n2,measured_ns,tuner_choice\n";
  const std::uint32_t n = quick ? 96 : 256;
  Cloth c = crumpled(n);
  for (BroadPhase b : {BroadPhase::uniform, BroadPhase::hashed}) {
    SelfCollisionSettings s = grid_settings(c, b);
    SelfCollisionEngine tuned(c.model, s);
    const double auto_ns = median_ns(tuned, c, 1, 7);
    SelfCollisionStats st;
    median_ns(tuned, c, 1, 1, &st);
    double best = 1e300, best_factor = 0;
    for (double factor : {1.0, 1.25, 1.5, 2.0, 2.5, 3.0, 4.0, 6.0}) {
      s.cell_size = Real(factor) * c.spacing;
      SelfCollisionEngine e(c.model, s);
      SelfCollisionStats fixed;
      const double ns = median_ns(e, c, 1, 7, &fixed);
      cell_size_row(out, b, n, factor, fixed, ns, false);
      if (ns < best) best = ns, best_factor = factor;
    }
    cell_size_row(out, b, n, st.cell_size / c.spacing, st, auto_ns, true);
    std::fprintf(stderr,
                 "  %-8s auto %.3g m: %.3g ms; best fixed (%.2g r): %.3g ms (auto/best %.2f)\n",
                 std::string(to_string(b)).c_str(), st.cell_size, auto_ns * 1e-6, best_factor,
                 best * 1e-6, auto_ns / best);
  }
}

void tuner(std::ostream& out, bool quick) {
  out << "broad_phase,side,cell_size_m,occupied_cells,model_P_n2,measured_ns,chosen\n";
  const std::uint32_t n = quick ? 96 : 256;
  Cloth c = crumpled(n);
  for (BroadPhase b : {BroadPhase::uniform, BroadPhase::hashed}) {
    SelfCollisionEngine e(c.model, grid_settings(c, b));
    e.apply(c.x.data(), c.v.data(), c.f.data(), 1);  // the first pass tunes
    for (const auto& r : e.last_tuning())
      out << to_string(b) << ',' << n << ',' << r.cell_size << ',' << r.occupied << ','
          << r.predicted << ',' << r.measured_ns << ',' << r.chosen << '\n';
  }
}

// The three exclusions on one grid: the cell the tuner picks without exclusion is then fixed
// for the other two, so that their distance tests, skipped cell pairs and times compare (left
// to the tuner, each could get another cell, and the counts would compare cell sizes).
void exclusion(std::ostream& out, bool quick) {
  out << "exclusion,side,particles,candidate_pairs,excluded_pairs,skipped_cells,contacts,"
         "exclusion_bytes,ns_per_particle_pass,cell_size_m\n";
  const std::uint32_t n = quick ? 96 : 256;
  Cloth c = crumpled(n);
  Real cell = 0;  // auto for the first (none), then its choice
  for (Exclusion x : {Exclusion::none, Exclusion::matrix, Exclusion::signature}) {
    SelfCollisionSettings s;
    s.radius = c.spacing;
    s.exclusion = x;
    s.cell_size = cell;
    SelfCollisionEngine e(c.model, s);
    SelfCollisionStats st;
    const double ns = median_ns(e, c, 1, 7, &st);
    cell = Real(st.cell_size);
    out << to_string(x) << ',' << n << ',' << n * n << ',' << st.candidate_pairs << ','
        << st.excluded << ',' << st.skipped_cells << ',' << st.contacts << ','
        << e.exclusion_bytes() << ',' << ns / double(n * n) << ',' << st.cell_size << '\n';
  }
}

void memory(std::ostream& out, bool quick) {
  out << "particles,exclusion,bytes,bytes_per_particle,dense_bit_matrix_bytes\n";
  for (std::uint32_t n :
       quick ? std::vector<std::uint32_t>{64, 128} : std::vector<std::uint32_t>{256, 1024}) {
    Model m;
    CrumpledClothParams p;
    p.n = n;
    build_crumpled_cloth(m, p, "cloth");
    m.prepare();
    for (Exclusion x : {Exclusion::matrix, Exclusion::signature}) {
      SelfCollisionSettings s;
      s.radius = p.size / Real(n - 1);
      s.exclusion = x;
      SelfCollisionEngine e(m, s);
      const double count = double(n) * n;
      out << n * n << ',' << to_string(x) << ',' << e.exclusion_bytes() << ','
          << double(e.exclusion_bytes()) / count << ',' << count * count / 8 << '\n';
    }
  }
}

void flag_wind(std::ostream& out, bool quick) {
  out << "scene,particles,self_collision,steps,ns_per_particle_step\n";
  const std::uint32_t n = 128;
  for (bool on : {false, true}) {
    Model m;
    FlagParams p;
    p.nx = p.ny = n;
    p.width = 1.5;
    p.height = 1;
    p.mass = 0.3;
    p.material = {300, 0.02};
    p.shear_stiffness = 100;
    p.bending_stiffness = 10;
    build_flag(m, p, "flag");
    m.fields.wind.velocity = {7, 0, 1.5};
    m.fields.wind.turbulence = Real(0.35);
    m.fields.air_drag = Real(0.05);
    if (on) {
      SelfCollisionSettings s;
      s.radius = Real(1.5 / 127);
      m.stages.push_back({"self_collision", Phase::forces,
                          [s](const Model& mm) { return make_self_collision_stage(mm, s); }});
    }
    SimulationSettings st;
    st.step = 5e-5;
    st.threads = 1;
    st.publish_every = kNeverEvery;
    st.sample_every = kNeverEvery;
    Simulator sim(std::move(m), st);
    const std::uint64_t steps = quick ? 100 : 1000;
    sim.run_steps(20);  // warm-up
    const auto t0 = WallClock::now();
    sim.run_steps(steps);
    const double ns = seconds_since(t0) * 1e9;
    const double pps = ns / double(steps) / double(n * n);
    std::fprintf(stderr, "  flag 128^2 in wind, self-collision %s: %.0f ns per particle-step\n",
                 on ? "on " : "off", pps);
    out << "flag_128_wind," << n * n << ',' << (on ? "on" : "off") << ',' << steps << ',' << pps
        << '\n';
  }
}

// The examples whose scene has a self-collision table, by file name.
std::vector<std::filesystem::path> self_colliding_examples(const std::filesystem::path& dir) {
  std::vector<std::filesystem::path> out;
  for (const auto& e : std::filesystem::directory_iterator(dir)) {
    if (e.path().extension() != ".toml") continue;
    auto scene = load_scene(e.path());
    if (!scene.ok()) {  // said, not hidden: a broken example is left out of the table
      std::fprintf(stderr, "  intersections: %s left out: %s\n", e.path().c_str(),
                   scene.error().to_string().c_str());
      continue;
    }
    for (const auto& st : scene->model.stages)
      if (st.name == kSelfCollisionStage.name) {
        out.push_back(e.path());
        break;
      }
  }
  std::sort(out.begin(), out.end());
  return out;
}

void intersections(std::ostream& out, bool quick, const std::filesystem::path& examples) {
  out << "example,integrator,solver,step,self_collision,simulated_s,steps,wall_s,"
         "most_intersecting_pairs,first_crossing_s\n";
  for (const auto& path : self_colliding_examples(examples)) {
    for (const bool on : {true, false}) {
      auto scene = load_scene(path);
      if (!scene.ok()) continue;
      Model& m = scene->model;
      if (!on)
        std::erase_if(m.stages, [](const StageSpec& s) { return s.name == kSelfCollisionStage.name; });
      SimulationSettings st = scene->settings;
      st.threads = 1;
      st.publish_every = kNeverEvery;
      st.sample_every = kNeverEvery;
      const double duration = std::min(st.duration, quick ? 0.25 : 6.0);
      const auto steps = static_cast<std::uint64_t>(std::llround(duration / st.step));
      const std::vector<Triangle> faces(m.surface.triangles.begin(), m.surface.triangles.end());
      Simulator sim(m, st);
      IntersectionCount count;
      std::size_t most = 0;
      double first = -1, wall = 0;
      for (std::uint64_t k = 0; k < steps; k += 10) {
        const auto t0 = WallClock::now();
        const bool ok = sim.run_steps(std::min<std::uint64_t>(10, steps - k));
        wall += seconds_since(t0);  // the counting is not the scene's cost
        const std::size_t n = count.count(sim.state().x(), faces);
        if (n > 0 && first < 0) first = sim.time();
        most = std::max(most, n);
        if (!ok) break;
      }
      const std::string solver =
          st.integrator == "implicit_euler" ? std::string(to_string(st.implicit.solver)) : "";
      std::fprintf(stderr, "  %s, self-collision %s: %zu crossing pairs at most, %.1f s\n",
                   path.stem().c_str(), on ? "on " : "off", most, wall);
      out << path.stem().string() << ',' << st.integrator << ',' << solver << ',' << st.step << ','
          << (on ? "on" : "off") << ',' << sim.time() << ',' << sim.steps_taken() << ',' << wall
          << ',' << most << ',' << first << '\n';
    }
  }
}

}  // namespace

void study_self_collision(const StudyOptions& o, const StudyWriter& write) {
  std::printf("maille study self-collision -> %s\n", o.out.string().c_str());
  write("scaling.csv", [&](std::ostream& f) { scaling(f, o.quick, o.threads); });
  write("cell_size.csv", [&](std::ostream& f) { cell_size(f, o.quick); });
  write("tuner.csv", [&](std::ostream& f) { tuner(f, o.quick); });
  write("exclusion.csv", [&](std::ostream& f) { exclusion(f, o.quick); });
  write("memory.csv", [&](std::ostream& f) { memory(f, o.quick); });
  write("flag_wind.csv", [&](std::ostream& f) { flag_wind(f, o.quick); });
  write("intersections.csv", [&](std::ostream& f) { intersections(f, o.quick, o.examples); });
}

}  // namespace maille::app
