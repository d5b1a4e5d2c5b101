// drape_quality: a scene's speed and its quality in one run, for the large-step frontier of
// docs/implicit.md (the target: real time at the largest step that keeps stretch <= 10 %, no
// crossing triangle pair, depth <= 2 mm).
//
//   drape_quality SCENE [--set KEY=VALUE]... [--threads N] [--duration T] [--every S]
//
// Runs SCENE (with the overrides, validated as `maille run --set`) for T simulated seconds
// (default: the scene's duration) and prints one CSV row with a header:
//
//   scene,points,step_s,sweeps,threads,wall_s_per_sim_s,max_stretch,max_depth_m,
//   max_crossing_pairs,stable,sim_s,final_mean_y_m
//
// wall_s_per_sim_s times the steps only. Every step: the deepest geometric obstacle (the
// stages' `obstacle_*_depth` gauges). Every S simulated seconds (default 1/60 s; at least every
// step), outside the timer: the largest stretch |x_b - x_a| / L0 - 1 over every spring-damper
// (structural, shear, bending) and, where the scene has self-collision, the pairs of its surface
// triangles that share no vertex and cross (an edge of one through the other: the test's
// witness, tests/intersections.hpp, with the boxes pruned by a sweep along x so that 128^2
// cloths are counted in milliseconds). final_mean_y_m, the points' mean height at the end, tells
// a cloth that has not come down (an unconverged solve at a large step can leave a stiff cloth
// hanging in the air, within every other bound).
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include "cloth_measures.hpp"
#include "intersections.hpp"
#include "maille/clock.hpp"
#include "maille/scene.hpp"
#include "maille/simulator.hpp"

namespace {

using namespace maille;

// Pairs of triangles sharing no vertex whose edges cross the other: count_self_intersections's
// test, the candidate pairs found by sorting the boxes along x and sweeping.
std::size_t crossing_pairs(std::span<const Vec3> x,
                           std::span<const std::array<std::uint32_t, 3>> tris) {
  struct Box {
    Vec3 lo, hi;
    std::uint32_t t;
  };
  std::vector<Box> boxes(tris.size());
  for (std::size_t t = 0; t < tris.size(); ++t) {
    const auto [a, b, c] = tris[t];
    boxes[t] = {{std::min({x[a].x, x[b].x, x[c].x}), std::min({x[a].y, x[b].y, x[c].y}),
                 std::min({x[a].z, x[b].z, x[c].z})},
                {std::max({x[a].x, x[b].x, x[c].x}), std::max({x[a].y, x[b].y, x[c].y}),
                 std::max({x[a].z, x[b].z, x[c].z})},
                static_cast<std::uint32_t>(t)};
  }
  std::sort(boxes.begin(), boxes.end(), [](const Box& p, const Box& q) { return p.lo.x < q.lo.x; });
  std::size_t count = 0;
  for (std::size_t s = 0; s < boxes.size(); ++s)
    for (std::size_t r = s + 1; r < boxes.size() && boxes[r].lo.x <= boxes[s].hi.x; ++r) {
      const Box &p = boxes[s], &q = boxes[r];
      if (p.hi.y < q.lo.y || q.hi.y < p.lo.y || p.hi.z < q.lo.z || q.hi.z < p.lo.z) continue;
      const auto& u = tris[p.t];
      const auto& w = tris[q.t];
      bool shared = false;
      for (auto i : u)
        for (auto j : w) shared |= i == j;
      if (shared) continue;
      bool hit = false;
      for (int e = 0; e < 3 && !hit; ++e) {
        hit |= test::segment_hits_triangle(x[u[e]], x[u[(e + 1) % 3]], x[w[0]], x[w[1]], x[w[2]]);
        hit |= test::segment_hits_triangle(x[w[e]], x[w[(e + 1) % 3]], x[u[0]], x[u[1]], x[u[2]]);
      }
      count += hit;
    }
  return count;
}

using test::largest_stretch;  // cloth_measures.hpp

int usage() {
  std::fprintf(stderr,
               "usage: drape_quality SCENE [--set KEY=VALUE]... [--threads N] [--duration T] "
               "[--every S]\n");
  return 2;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 2) return usage();
  const std::string path = argv[1];
  std::vector<std::string> overrides;
  int threads = 0;
  double duration = 0, every = 1.0 / 60;
  for (int i = 2; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--set" && i + 1 < argc) {
      overrides.push_back(argv[++i]);
    } else if (a == "--threads" && i + 1 < argc) {
      threads = std::atoi(argv[++i]);
    } else if (a == "--duration" && i + 1 < argc) {
      duration = std::atof(argv[++i]);
    } else if (a == "--every" && i + 1 < argc) {
      every = std::atof(argv[++i]);
    } else {
      return usage();
    }
  }
  auto loaded = load_scene(path, overrides);
  if (!loaded) {
    std::fprintf(stderr, "drape_quality: %s\n", loaded.error().to_string().c_str());
    return 1;
  }
  Scene scene = std::move(loaded.value());
  scene.settings.backend = "cpu";
  if (threads > 0) scene.settings.threads = threads;
  scene.settings.publish_every = kNeverEvery;
  const bool self_colliding =
      std::any_of(scene.model.stages.begin(), scene.model.stages.end(),
                  [](const StageSpec& st) { return st.name == "self_collision"; });
  const auto triangles = scene.model.surface.triangles;
  const std::string name = scene.name;
  Simulator sim(std::move(scene.model), scene.settings);
  const double h = sim.settings().step;
  if (duration <= 0) duration = sim.settings().duration;
  const auto steps = static_cast<std::uint64_t>(std::llround(duration / h));
  const auto sample =
      std::max<std::uint64_t>(1, static_cast<std::uint64_t>(std::llround(every / h)));
  double wall = 0, stretch = 0, depth = 0;
  std::size_t crossing = 0;
  bool stable = true;
  std::uint64_t done = 0;
  for (std::uint64_t k = 1; k <= steps; ++k) {
    const auto t0 = WallClock::now();
    const bool ok = sim.step();
    wall += seconds_since(t0);
    if (!ok) {
      stable = false;
      break;
    }
    done = k;
    for (const auto& gauge : sim.profile().gauges())
      if (gauge.name.starts_with("obstacle_") && gauge.name.ends_with("_depth"))
        depth = std::max(depth, gauge.last);
    if (k % sample == 0 || k == steps) {
      stretch = std::max(stretch, largest_stretch(sim));
      if (self_colliding) crossing = std::max(crossing, crossing_pairs(sim.state().x(), triangles));
    }
  }
  const double sim_s = static_cast<double>(done) * h;
  std::printf(
      "scene,points,step_s,sweeps,threads,wall_s_per_sim_s,max_stretch,max_depth_m,"
      "max_crossing_pairs,stable,sim_s,final_mean_y_m\n");
  double mean_y = 0;
  for (const Vec3& p : sim.state().x()) mean_y += p.y;
  mean_y /= static_cast<double>(std::max<std::size_t>(sim.state().size(), 1));
  std::printf("%s,%zu,%.9g,%d,%d,%.4g,%.4g,%.4g,%zu,%d,%.4g,%.4g\n", name.c_str(),
              static_cast<std::size_t>(sim.model().points.size()), h,
              sim.settings().implicit.iterations, sim.threads(), sim_s > 0 ? wall / sim_s : 0.0,
              stretch, depth, crossing, stable ? 1 : 0, sim_s, mean_y);
  return stable ? 0 : 1;
}
