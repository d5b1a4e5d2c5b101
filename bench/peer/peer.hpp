// The peer comparison: one scene, two engines, one measuring function.
//
//   PeerScene     the physical scene both engines build: a square cloth of side L and mass M,
//                 n x n particles, flat and horizontal, dropped on a fixed sphere
//   ClothMeter    the metrics, computed identically for both engines from the particles'
//                 positions at every step (grid order: particle (i, j) is j * n + i)
//   RunResult     what one run measured
//
// Each engine's side (maille_cloth.cpp, bullet_cloth.cpp) builds the scene, steps it with a
// given step and setting, and hands its positions to a ClothMeter after every step; only the
// stepping is timed.
#pragma once

#include <array>
#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

namespace peer {

struct PeerScene {
  int n = 32;                  // particles per side (n x n)
  double side = 1.0;           // L, m
  double mass = 0.3;           // M, kg, total, shared equally
  double height = 0.75;        // m, the cloth's starting plane y (the sphere's top is at R)
  double radius = 0.25;        // R, m, the sphere's radius; centred at the origin
  double gravity = 9.81;       // m/s^2, along -y
  double duration = 2.0;       // T, s simulated
  double stiffness = 2000.0;   // N/m, Maille's structural springs (shear: a quarter)
  double link_damping = 0.02;  // N.s/m, Maille's damping on every spring
  double rest() const { return side / (n - 1); }
  int particles() const { return n * n; }
};

struct RunResult {
  double step = 0;             // s
  double sim_s = 0;            // simulated seconds reached (T unless it failed early)
  double wall_s = 0;           // s of stepping (metrics excluded)
  double max_penetration = 0;  // m, into the exact sphere, over every step
  double max_stretch = 0;      // max over structural edges and steps of |xi - xj| / rest - 1
  double final_clearance = 0;  // m, min over particles of |x - c| - R at the end (< 0: inside)
  double final_centre_y = 0;   // m, the cloth's middle particle at the end
  bool stable = false;         // finite, bounded, within the setting's Bounds, moved
  std::string why;             // why it is not stable ("" when it is)
  std::string detail;          // engine-specific notes (Maille: the stages' cost per particle-step)
  bool frozen() const { return why.rfind("frozen", 0) == 0; }
  double wall_per_sim() const { return sim_s > 0 ? wall_s / sim_s : 0; }
};

// What "stable" means. Every run: every coordinate finite and within 10 L of the origin (and no
// blow-up reported by the engine), no structural edge ever beyond `max_stretch` (9: ten times
// its rest length, a cloth torn apart), no particle ever deeper than `max_penetration` in the
// sphere (R / 2 by default: the cloth did not go through), and the cloth's middle ended at least
// R / 2 below where it started (a step so small that single-precision positions never move is
// not a simulation). Tuned settings ask more of the step: at most 5 mm deep and 30 % stretch.
// Tuned settings ask more of the step: `max_penetration` = 5 mm. A cloth that slides off the
// sphere (a frictionless contact lets it) is not unstable: `final_centre_y` says where its
// middle ended.
struct Bounds {
  double max_penetration = -1;  // m; < 0: R / 2
  double max_stretch = 9;       // |xi - xj| / rest - 1 over structural edges
};

class ClothMeter {
 public:
  ClothMeter(const PeerScene& s, const Bounds& b)
      : s_(s),
        max_pen_(b.max_penetration < 0 ? 0.5 * s.radius : b.max_penetration),
        max_stretch_(b.max_stretch) {}

  // One sample: positions in grid order, as a function x(i) -> {x, y, z}. False when the state
  // already breaks a bound (the run stops there, unstable).
  template <class Get>
  bool sample(Get&& x) {
    const int n = s_.n;
    const double bound = 10 * s_.side, rest = s_.rest();
    double clearance = 1e300;
    for (int p = 0; p < n * n; ++p) {
      const std::array<double, 3> a = x(p);
      if (!std::isfinite(a[0]) || !std::isfinite(a[1]) || !std::isfinite(a[2]))
        return fail("non-finite position");
      if (std::abs(a[0]) > bound || std::abs(a[1]) > bound || std::abs(a[2]) > bound)
        return fail("a particle left the 10 L box");
      const double d = std::sqrt(a[0] * a[0] + a[1] * a[1] + a[2] * a[2]) - s_.radius;
      clearance = std::min(clearance, d);
      const int i = p % n, j = p / n;
      if (i + 1 < n) stretch(a, x(p + 1), rest);
      if (j + 1 < n) stretch(a, x(p + n), rest);
    }
    r_.final_clearance = clearance;
    r_.max_penetration = std::max(r_.max_penetration, -clearance);
    r_.final_centre_y = x((n / 2) * n + n / 2)[1];
    if (r_.max_penetration > max_pen_) return fail("deeper than the bound in the sphere");
    if (r_.max_stretch > max_stretch_) return fail("stretched beyond the bound");
    return true;
  }

  // Ends the run: the result with its timing, stability decided.
  RunResult finish(double step, double sim_s, double wall_s) {
    r_.step = step, r_.sim_s = sim_s, r_.wall_s = wall_s;
    if (r_.why.empty() && r_.final_centre_y > s_.height - 0.5 * s_.radius)
      r_.why = "frozen (the cloth did not fall)";
    r_.stable = r_.why.empty();
    return r_;
  }
  bool fail(const std::string& why) {
    if (r_.why.empty()) r_.why = why;
    return false;
  }

 private:
  void stretch(const std::array<double, 3>& a, const std::array<double, 3>& b, double rest) {
    const double dx = a[0] - b[0], dy = a[1] - b[1], dz = a[2] - b[2];
    r_.max_stretch = std::max(r_.max_stretch, std::sqrt(dx * dx + dy * dy + dz * dz) / rest - 1);
  }

  PeerScene s_;
  double max_pen_, max_stretch_;
  RunResult r_;
};

// ---- Maille (maille_cloth.cpp) ----------------------------------------------------------
struct MailleSetting {
  std::string name = "default";
  std::string integrator = "leapfrog";  // the scene's [simulation] integrator
  std::string method = "geometric";     // the [[obstacle]] method
  std::string obstacle_keys;            // extra [[obstacle]] keys ("" : the method's defaults)
  Bounds bounds;                        // what this setting must hold to count as stable
  std::string implicit_keys;            // [simulation.implicit] keys ("": none)
  std::string describe() const;
};
std::string maille_version();
// Maille's own estimate of the largest stable step for this scene and setting (s).
double maille_estimate(const PeerScene& s, const MailleSetting& m);
RunResult run_maille(const PeerScene& s, const MailleSetting& m, double step);

// ---- Bullet (bullet_cloth.cpp) ----------------------------------------------------------
struct BulletSetting {
  std::string name = "default";
  int piterations = -1;  // position (link) solver iterations; -1: Bullet's default
  int citerations = -1;  // cluster iterations; -1: default (unused without clusters)
  double margin = -1;    // soft body collision margin, m; -1: Bullet's default
  double kDP = -1;       // damping coefficient [0, 1]; -1: default
  double kCHR = -1;      // rigid contact hardness [0, 1]; -1: default
  double kDF = -1;       // dynamic friction [0, 1]; -1: default
  double voxel = -1;     // the sparse SDF's voxel size, m (rigid contacts); -1: default
  Bounds bounds;         // what this setting must hold to count as stable
  std::string describe() const;
};
std::string bullet_version();
RunResult run_bullet(const PeerScene& s, const BulletSetting& b, double step);
// Bullet's default configuration as read from a fresh btSoftBody (for the report).
std::string bullet_defaults();

}  // namespace peer
