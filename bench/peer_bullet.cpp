// peer_bullet: Maille against Bullet's soft-body cloth on the same scene (docs/peer.md).
//
//   peer_bullet --out DIR [--quick] [--sizes 32,64,128] [--duration T] [--engine maille|bullet]
//               [--settings default,tuned] [--large-steps [--rates 60,120,240] [--sweeps 10]]
//
// A square cloth (1 m, 0.3 kg, structural + shear springs) dropped flat from 0.5 m above a
// fixed sphere (R = 0.25 m), n x n particles for n = 32, 64, 128; each engine with its default
// settings and tuned, each at its own largest stable step, found on a ladder of steps (factor
// 2^-1/4 from 0.1 s, the first stable one wins). Writes DIR/peer.csv (atomically: a
// temporary file renamed when whole):
//
//   engine,version,particles,setting,step_s,wall_s_per_sim_s,max_penetration_m,max_stretch,
//   stable,sim_s,threads,final_clearance_m,rungs,notes
//
// `--quick`: 32 and 64 only, 0.5 s simulated (the ctest). The full run simulates 2 s.
// `--large-steps`: Maille's implicit Euler by vertex block descent (10 sweeps, geometric sphere
// in the solve) also runs at the animation steps 1/60, 1/120 and 1/240 s, no ladder: rows with
// setting vbd_60, vbd_120, vbd_240, held to the tuned bounds (docs/implicit.md). `--rates` picks
// the steps (per second) and `--sweeps` the sweep counts (a row per pair; a count other than 10
// is named vbd_60_s15 and so on).
// `--settings`: which of the ladders' settings run (default both, default and tuned), each
// for both engines or for one (`bullet.tuned`): `--large-steps --settings bullet.tuned` runs
// only the VBD rows and Bullet tuned's ladder (the default ladders take minutes at 128^2, where
// Bullet's defaults hold at no step).
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iostream>
#include <sstream>
#include <string>
#include <vector>

#include "peer/peer.hpp"

namespace {

using peer::RunResult;

struct Row {
  std::string engine, version, setting, notes;
  int particles = 0;
  RunResult r;
  int rungs = 0;
};

// The ladder, the same for both engines: h = 0.1 s x 2^(-k/4), k = 0, 1, ... down to 1e-5 s
// (2^(-k/2), down to 0.1 ms, with --quick);
// the first stable run is the engine's largest stable step. When none is, the smallest step
// tried that still moved (below it single-precision positions freeze) is reported, unstable.
Row ladder(const std::function<RunResult(double)>& run, Row row, bool quick) {
  const double factor = quick ? 0.5 : 0.25;
  const double bottom = quick ? 0.99e-4 : 0.99e-5;
  for (int k = 0; 0.1 * std::pow(2.0, -factor * k) >= bottom; ++k) {
    const double h = 0.1 * std::pow(2.0, -factor * k);
    const RunResult r = run(h);
    if (r.frozen() && k > 0) {
      std::printf("    %-7s %-7s n=%-5d h=%.3e: frozen; no stable step on the ladder\n",
                  row.engine.c_str(), row.setting.c_str(), row.particles, h);
      break;
    }
    row.r = r;
    row.rungs = k + 1;
    std::printf("    %-7s %-7s n=%-5d h=%.3e: %s%s\n", row.engine.c_str(), row.setting.c_str(),
                row.particles, h, row.r.stable ? "stable" : "unstable: ", row.r.why.c_str());
    std::fflush(stdout);
    if (row.r.stable) break;
  }
  if (!row.r.stable) row.notes += " no stable step on the ladder";
  return row;
}

std::string clean(std::string s) {
  for (char& c : s)
    if (c == ',' || c == '\n' || c == '"') c = ';';
  return s;
}

void write_csv(const std::filesystem::path& dir, const std::vector<Row>& rows) {
  std::filesystem::create_directories(dir);
  const std::filesystem::path file = dir / "peer.csv", tmp = dir / "peer.csv.tmp";
  {
    std::ofstream f(tmp);
    f.precision(6);
    f << "engine,version,particles,setting,step_s,wall_s_per_sim_s,max_penetration_m,"
         "max_stretch,stable,sim_s,threads,final_clearance_m,rungs,notes\n";
    for (const Row& w : rows)
      f << w.engine << ',' << clean(w.version) << ',' << w.particles << ',' << w.setting << ','
        << w.r.step << ',' << w.r.wall_per_sim() << ',' << w.r.max_penetration << ','
        << w.r.max_stretch << ',' << (w.r.stable ? 1 : 0) << ',' << w.r.sim_s << ",1,"
        << w.r.final_clearance << ',' << w.rungs << ','
        << clean(w.notes + w.r.detail + (w.r.why.empty() ? "" : " (" + w.r.why + ")")) << '\n';
    f.flush();
    if (!f) throw std::runtime_error("cannot write " + tmp.string());
  }
  std::filesystem::rename(tmp, file);
}

int usage() {
  std::fprintf(stderr,
               "usage: peer_bullet --out DIR [--quick] [--sizes 32,64,128] [--duration T] "
               "[--engine maille|bullet] [--settings default,tuned,bullet.tuned] [--large-steps "
               "[--rates 60,120,240] [--sweeps 10]]\n");
  return 2;
}

}  // namespace

int main(int argc, char** argv) {
  std::string out;
  bool quick = false;
  std::vector<int> sizes;
  double duration = 0;
  std::string engine;  // "": both
  bool large_steps = false;
  std::vector<int> rates, sweeps;
  std::vector<std::string> settings;
  const auto ints = [](const char* text) {
    std::vector<int> values;
    std::stringstream list(text);
    for (std::string item; std::getline(list, item, ',');)
      values.push_back(std::atoi(item.c_str()));
    return values;
  };
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--out" && i + 1 < argc) {
      out = argv[++i];
    } else if (a == "--quick") {
      quick = true;
    } else if (a == "--large-steps") {
      large_steps = true;
    } else if (a == "--sizes" && i + 1 < argc) {
      sizes = ints(argv[++i]);
    } else if (a == "--rates" && i + 1 < argc) {
      rates = ints(argv[++i]);
    } else if (a == "--sweeps" && i + 1 < argc) {
      sweeps = ints(argv[++i]);
    } else if (a == "--settings" && i + 1 < argc) {
      std::stringstream list(argv[++i]);
      for (std::string item; std::getline(list, item, ',');) {
        const std::string bare = item.substr(item.find('.') + 1);
        const std::string who =
            item.find('.') == std::string::npos ? "" : item.substr(0, item.find('.'));
        if ((bare != "default" && bare != "tuned") ||
            (who != "" && who != "maille" && who != "bullet"))
          return usage();
        settings.push_back(item);
      }
    } else if (a == "--engine" && i + 1 < argc) {
      engine = argv[++i];
      if (engine != "maille" && engine != "bullet") return usage();
    } else if (a == "--duration" && i + 1 < argc) {
      duration = std::atof(argv[++i]);
    } else {
      return usage();
    }
  }
  if (out.empty()) return usage();
  if (sizes.empty()) sizes = quick ? std::vector<int>{32, 64} : std::vector<int>{32, 64, 128};
  for (int n : sizes)
    if (n < 2 || n > 1024) return usage();
  if (duration <= 0) duration = quick ? 0.5 : 2.0;
  if (rates.empty()) rates = {60, 120, 240};
  if (sweeps.empty()) sweeps = {10};
  if (settings.empty()) settings = {"default", "tuned"};
  for (int r : rates)
    if (r < 1 || r > 100000) return usage();
  for (int k : sweeps)
    if (k < 1 || k > 100000) return usage();
  const auto wanted = [&](const std::string& who, const std::string& name) {
    return std::find(settings.begin(), settings.end(), name) != settings.end() ||
           std::find(settings.begin(), settings.end(), who + "." + name) != settings.end();
  };

  // Default settings: each engine as it comes. Tuned: see docs/peer.md for how they were chosen.
  const peer::MailleSetting maille_default{};
  const peer::MailleSetting maille_tuned{
      "tuned", "leapfrog", "facets", "alpha = 0.0\nbeta = 0.2\n", peer::Bounds{0.005, 0.3}, ""};
  const peer::BulletSetting bullet_default{};
  peer::BulletSetting bullet_tuned;
  bullet_tuned.name = "tuned";
  bullet_tuned.piterations = 16;
  bullet_tuned.margin = 0.01;
  bullet_tuned.voxel = 0.05;
  bullet_tuned.bounds = peer::Bounds{0.005, 0.3};

  std::printf("peer_bullet -> %s/peer.csv (%s, %.2f s simulated, one thread)\n", out.c_str(),
              quick ? "quick" : "full", duration);
  std::printf("  Maille %s; Bullet %s, defaults: %s\n", peer::maille_version().c_str(),
              peer::bullet_version().c_str(), peer::bullet_defaults().c_str());
  std::vector<Row> rows;
  try {
    for (int n : sizes) {
      peer::PeerScene s;
      s.n = n;
      s.duration = duration;
      for (const peer::MailleSetting& m : {maille_default, maille_tuned}) {
        if (engine == "bullet") break;
        if (!wanted("maille", m.name)) continue;
        const double estimate = peer::maille_estimate(s, m);
        Row row{"maille",
                peer::maille_version(),
                m.name,
                m.describe() + " estimate=" + std::to_string(estimate),
                s.particles(),
                {},
                0};
        rows.push_back(ladder([&](double h) { return peer::run_maille(s, m, h); }, row, quick));
      }
      for (const int per_second : rates)
        for (const int k : sweeps) {
          if (!large_steps || engine == "bullet") break;
          const std::string name = "vbd_" + std::to_string(per_second) +
                                   (k == 10 ? std::string() : "_s" + std::to_string(k));
          const peer::MailleSetting v{name,
                                      "implicit_euler",
                                      "geometric",
                                      "",
                                      peer::Bounds{0.005, 0.3},
                                      "solver = \"vbd\"\niterations = " + std::to_string(k) + "\n"};
          Row row{"maille", peer::maille_version(), v.name, v.describe(), s.particles(), {}, 1};
          row.r = peer::run_maille(s, v, 1.0 / per_second);
          std::printf("    maille  %-7s n=%-5d h=1/%d: %s%s\n", v.name.c_str(), s.particles(),
                      per_second, row.r.stable ? "stable" : "unstable: ", row.r.why.c_str());
          rows.push_back(row);
        }
      for (const peer::BulletSetting& b : {bullet_default, bullet_tuned}) {
        if (engine == "maille") break;
        if (!wanted("bullet", b.name)) continue;
        Row row{"bullet", peer::bullet_version(), b.name, b.describe(), s.particles(), {}, 0};
        rows.push_back(ladder([&](double h) { return peer::run_bullet(s, b, h); }, row, quick));
      }
    }
    write_csv(out, rows);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "peer_bullet: %s\n", e.what());
    return 1;
  }
  for (const Row& w : rows)
    std::printf("  %-6s %-7s %6d  h %.3e s  %8.3f s/s  pen %.2e m  stretch %.3f  %s\n",
                w.engine.c_str(), w.setting.c_str(), w.particles, w.r.step, w.r.wall_per_sim(),
                w.r.max_penetration, w.r.max_stretch, w.r.stable ? "stable" : "UNSTABLE");
  return 0;
}
