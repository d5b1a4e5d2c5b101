// `maille study obstacles`: the three obstacle methods (geometric, facets, conditional) on the
// same shapes, so that their errors and costs compare. CSV files:
//
//   obstacles.csv  a 24 x 24 cloth dropped on a sphere, a cube and a rotated cube, per method:
//                  the deepest penetration into the true (canonical) shape over the run, the
//                  mean contacts per step, and the cost of the obstacle stage beside the link
//                  forces' (ns per particle-step, one run each: compare within a row)
//   incline.csv    a bead released on a plane tilted by theta: the distance slid in T against
//                  the analytic 0.5 g (sin theta - mu cos theta) T^2 (mu = beta for facets; the
//                  geometric and conditional methods have no friction: mu = 0)
//   lean.csv       the canonical force mapped through M_d under a non-uniform scale: its angle
//                  to the ellipsoid's true normal, over the surface, per aspect ratio
//                  (the `normal = "world"` variant is along the normal by construction)
//
// The cloth starts 0.8 m up, clear of every shape (the rotated cube's corner reaches 0.73 m).
// Scenes are built as scene text and read by the scene reader, so every number comes from the
// same path a user's scene takes.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <ostream>
#include <sstream>
#include <stdexcept>

#include "maille/geometric_point.hpp"
#include "maille/obstacle.hpp"
#include "maille/scene.hpp"
#include "maille/simulator.hpp"
#include "study.hpp"

namespace maille::app {

namespace {

constexpr double kPi = std::numbers::pi;

// The method's own keys, with values that hold a 24 x 24 cloth of 0.3 kg at h = 2e-4 s.
std::string method_keys(const std::string& method) {
  if (method == "geometric") return "stiffness = 2000.0\ndamping = 0.5\n";
  if (method == "facets") return "alpha = 0.0\nbeta = 0.0\n";
  return "threshold = 0.02\nstiffness = 500.0\ndamping = 0.2\n";
}

Scene read(const std::string& text) {
  auto scene = parse_scene(text, "study.toml", LinkKindRegistry::with_builtins(),
                           StageRegistry::with_builtins());
  if (!scene) throw std::runtime_error("study scene: " + scene.error().to_string());
  scene->settings.threads = 1;
  scene->settings.publish_every = kNeverEvery;
  scene->settings.sample_every = kNeverEvery;
  return std::move(*scene);
}

struct Shape {
  const char* label;
  const char* shape;
  Vec3 rotation;
};

std::string cloth_on(const Shape& s, const std::string& method) {
  std::ostringstream t;
  t << "[simulation]\nstep = 2e-4\n[fields]\ngravity = [0.0, -9.81, 0.0]\nair_drag = 0.2\n"
       "[[flag]]\nname = \"cloth\"\norigin = [-0.5, 0.8, -0.5]\nalong = [1.0, 0.0, 0.0]\n"
       "up = [0.0, 0.0, 1.0]\nwidth = 1.0\nheight = 1.0\nresolution = [24, 24]\nmass = 0.3\n"
       "stiffness = 400.0\nshear_stiffness = 100.0\nbending_stiffness = 1.0\ndamping = 0.02\n"
       "fixed = \"none\"\n"
       "[[obstacle]]\nname = \"shape\"\nshape = \""
    << s.shape << "\"\nmethod = \"" << method
    << "\"\nposition = [0.0, 0.3, 0.0]\nscale = [0.25, 0.25, 0.25]\nrotation = [" << s.rotation.x
    << ", " << s.rotation.y << ", " << s.rotation.z << "]\n"
    << method_keys(method) << "collides_with = [\"cloth\"]\n";
  return t.str();
}

double stage_ns(const Simulator& sim, const std::string& name) {
  for (const auto& st : sim.profile().stages())
    if (st.name == name) return st.total_ns;
  return 0;
}

std::uint64_t counter_total(const Simulator& sim, const std::string& name) {
  for (const auto& c : sim.profile().counters())
    if (c.name == name) return c.total;
  return 0;
}

void cloth_table(std::ostream& f, bool quick) {
  const Shape shapes[] = {{"sphere", "sphere", {0, 0, 0}},
                          {"cube", "cube", {0, 0, 0}},
                          {"rotated_cube", "cube", {30, 20, 10}}};
  const std::uint64_t steps = quick ? 2500 : 7500;  // 0.5 s or 1.5 s
  f << "shape,method,particles,steps,max_penetration_m,mean_contacts,obstacle_ns_pps,"
       "link_ns_pps\n";
  for (const Shape& s : shapes)
    for (const std::string& method : name_strings<ObstacleMethod>()) {
      Scene scene = read(cloth_on(s, method));
      const shapes::Affine place =
          shapes::Affine::from({0, Real(0.3), 0}, s.rotation, {Real(0.25), Real(0.25), Real(0.25)});
      const ShapeKind kind = shape_kind(s.shape);
      Simulator sim(std::move(scene.model), scene.settings);
      double deepest = 0;
      for (std::uint64_t i = 0; i < steps; ++i) {
        if (!sim.step()) throw std::runtime_error("study: " + sim.blow_up()->message);
        if (i % 10) continue;
        for (const Vec3& x : sim.state().x()) {
          const Real d = shapes::canonical(kind, place.to_canonical(x)).signed_distance;
          deepest = std::max(deepest, -double(d) * 0.25);  // canonical -> world (scale 0.25)
        }
      }
      const double pps = double(steps) * double(sim.state().size());
      f << s.label << ',' << method << ',' << sim.state().size() << ',' << steps << ',' << deepest
        << ',' << double(counter_total(sim, "obstacle_shape_contacts")) / double(steps) << ','
        << stage_ns(sim, "obstacle:shape") / pps << ',' << stage_ns(sim, "link_forces") / pps
        << '\n';
      std::printf("  %-12s %-11s deepest %.2e m, obstacle %.1f ns/pps, links %.1f ns/pps\n",
                  s.label, method.c_str(), deepest, stage_ns(sim, "obstacle:shape") / pps,
                  stage_ns(sim, "link_forces") / pps);
    }
}

// A bead set on a plane tilted by theta about z, released at rest; T seconds later.
void incline_table(std::ostream& f, bool quick) {
  const double g = 9.81, theta_deg = 25, T = quick ? 0.5 : 1.0, h = 1e-4;
  const double theta = theta_deg * kPi / 180;
  struct Case {
    std::string method;
    double mu;
    std::string keys;
  };
  const Case cases[] = {
      {"geometric", 0, "stiffness = 2000.0\ndamping = 0.5\n"},
      {"facets", 0, "alpha = 0.0\nbeta = 0.0\n"},
      {"facets", 0.2, "alpha = 0.0\nbeta = 0.2\n"},
      {"facets", 0.4, "alpha = 0.0\nbeta = 0.4\n"},
      {"conditional", 0, "threshold = 0.02\nstiffness = 500.0\ndamping = 0.2\n"},
  };
  f << "method,mu,theta_deg,seconds,distance_m,analytic_m,relative_error\n";
  for (const Case& c : cases) {
    // The bead starts on the surface the method holds it at: on the plane (facets), m g cos / k
    // into it (geometric), or at the conditional shell's height (threshold, less the sag).
    std::ostringstream t;
    t << "[simulation]\nstep = " << h
      << "\n[[mass]]\nname = \"bead\"\nmass = 0.01\nposition = [0.0, 0.0000001, 0.0]\n"
         "[[obstacle]]\nname = \"incline\"\nshape = \"plane\"\nmethod = \""
      << c.method << "\"\nscale = [20.0, 1.0, 20.0]\nrotation = [0.0, 0.0, " << theta_deg
      << "]\nresolution = 8\n"
      << c.keys;
    Scene scene = read(t.str());
    if (c.method == "conditional")  // settle it on the sampled shell first, along the normal
      scene.model.points.initial_position[0] =
          Vec3{-std::sin(Real(theta)), std::cos(Real(theta)), 0} * Real(0.019);
    Simulator sim(std::move(scene.model), scene.settings);
    const Vec3 start = sim.state().x()[0];
    sim.run_steps(std::uint64_t(T / h));
    const Vec3 down{-std::cos(Real(theta)), -std::sin(Real(theta)), 0};
    const double d = dot(sim.state().x()[0] - start, down);
    const double analytic = 0.5 * g * (std::sin(theta) - c.mu * std::cos(theta)) * T * T;
    f << c.method << ',' << c.mu << ',' << theta_deg << ',' << T << ',' << d << ',' << analytic
      << ',' << std::abs(d - analytic) / analytic << '\n';
    std::printf("  incline %-11s mu %.1f: slid %.4f m, analytic %.4f m\n", c.method.c_str(), c.mu,
                d, analytic);
  }
}

// Over the ellipsoid x^2/a^2 + y^2/b^2 + z^2/c^2 = 1 (a sphere scaled a, b, c), points just
// inside the surface: the angle between the canonical force mapped through M_d and the true
// normal.
void lean_table(std::ostream& f) {
  f << "scale_x,scale_y,scale_z,mean_lean_deg,max_lean_deg\n";
  const Vec3 scales[] = {{1, 1, 1}, {1, 0.8, 1}, {1, 0.5, 1}, {1, 0.5, 0.25}, {1, 0.2, 0.2}};
  for (const Vec3& s : scales) {
    GeometricPoint g;
    const shapes::Affine place = shapes::Affine::from({}, {}, s);
    double sum = 0, most = 0;
    int n = 0;
    for (int i = 1; i < 30; ++i)
      for (int j = 0; j < 60; ++j) {
        const double th = kPi * i / 30, ph = 2 * kPi * j / 60;
        const Vec3 u{Real(std::sin(th) * std::cos(ph)), Real(std::cos(th)),
                     Real(std::sin(th) * std::sin(ph))};
        const Vec3 x = place.to_world(u * Real(0.99));
        Real depth = 0;
        const Vec3 force = geometric_contact_force(g, place, x, {}, 1000, 0, false, depth);
        const Vec3 normal = place.normal_to_world(u);
        const double c = std::clamp(double(dot(force / norm(force), normal)), -1.0, 1.0);
        const double lean = std::acos(c) * 180 / kPi;
        sum += lean, most = std::max(most, lean), ++n;
      }
    f << s.x << ',' << s.y << ',' << s.z << ',' << sum / n << ',' << most << '\n';
    std::printf("  lean under scale (%g, %g, %g): mean %.2f deg, max %.2f deg\n", s.x, s.y, s.z,
                sum / n, most);
  }
}

}  // namespace

void study_obstacles(const StudyOptions& o, const StudyWriter& write) {
  std::printf("maille study obstacles -> %s\n", o.out.string().c_str());
  write("obstacles.csv", [&](std::ostream& f) { cloth_table(f, o.quick); });
  write("incline.csv", [&](std::ostream& f) { incline_table(f, o.quick); });
  write("lean.csv", [&](std::ostream& f) { lean_table(f); });
}

}  // namespace maille::app
