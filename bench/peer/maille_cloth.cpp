// Maille's side of the peer comparison: the scene as scene text, read by the scene reader (the
// path a user's scene takes), stepped on one thread.
#include <chrono>
#include <cstdio>
#include <sstream>
#include <stdexcept>

#include "maille/scene.hpp"
#include "maille/simulator.hpp"
#include "peer.hpp"

#ifndef MAILLE_VERSION_STRING
#define MAILLE_VERSION_STRING "unknown"
#endif

namespace peer {

namespace {

// The cloth is a [[flag]] with no fixed point, lying in the plane y = height (along x, "up"
// along z), structural + shear springs (no bending springs: Bullet's patch has none either);
// the sphere an [[obstacle]] of radius R at the origin.
std::string scene_text(const PeerScene& s, const MailleSetting& m, double step) {
  std::ostringstream t;
  t.precision(17);
  t << "[simulation]\nintegrator = \"" << m.integrator << "\"\nstep = " << step << "\n";
  if (!m.implicit_keys.empty()) t << "[simulation.implicit]\n" << m.implicit_keys;
  t << "[fields]\ngravity = [0.0, " << -s.gravity << ", 0.0]\n"
    << "[[flag]]\nname = \"cloth\"\norigin = [" << -s.side / 2 << ", " << s.height << ", "
    << -s.side / 2 << "]\nalong = [1.0, 0.0, 0.0]\nup = [0.0, 0.0, 1.0]\nwidth = " << s.side
    << "\nheight = " << s.side << "\nresolution = [" << s.n << ", " << s.n << "]\nmass = " << s.mass
    << "\nstiffness = " << s.stiffness << "\nshear_stiffness = " << s.stiffness / 4
    << "\nbending_stiffness = 0.0\ndamping = " << s.link_damping << "\nfixed = \"none\"\n"
    << "[[obstacle]]\nname = \"sphere\"\nshape = \"sphere\"\nmethod = \"" << m.method
    << "\"\nposition = [0.0, 0.0, 0.0]\nscale = [" << s.radius << ", " << s.radius << ", "
    << s.radius << "]\n"
    << m.obstacle_keys << "collides_with = [\"cloth\"]\n";
  return t.str();
}

maille::Scene read(const PeerScene& s, const MailleSetting& m, double step) {
  auto scene = maille::parse_scene(scene_text(s, m, step), "peer.toml",
                                   maille::LinkKindRegistry::with_builtins(),
                                   maille::StageRegistry::with_builtins());
  if (!scene) throw std::runtime_error("peer scene: " + scene.error().to_string());
  scene->settings.threads = 1;  // one thread, as Bullet
  scene->settings.publish_every = maille::kNeverEvery;
  return std::move(*scene);
}

}  // namespace

std::string MailleSetting::describe() const {
  std::string d = "integrator=" + integrator + " obstacle=" + method;
  if (!implicit_keys.empty()) {
    std::string k = implicit_keys;
    for (char& c : k)
      if (c == '\n') c = ' ';
    d += " " + k;
  }
  if (!obstacle_keys.empty()) {
    std::string k = obstacle_keys;
    for (char& c : k)
      if (c == '\n') c = ' ';
    d += " " + k;
    while (!d.empty() && d.back() == ' ') d.pop_back();
  }
  return d;
}

std::string maille_version() {
  return MAILLE_VERSION_STRING;
}

double maille_estimate(const PeerScene& s, const MailleSetting& m) {
  maille::Scene scene = read(s, m, 1e-4);
  maille::Simulator sim(std::move(scene.model), scene.settings);
  return double(sim.stability().max_step);
}

RunResult run_maille(const PeerScene& s, const MailleSetting& m, double step) {
  maille::Scene scene = read(s, m, step);
  maille::Simulator sim(std::move(scene.model), scene.settings);
  ClothMeter meter(s, m.bounds);
  const auto steps = std::uint64_t(std::llround(s.duration / step));
  const auto get = [&](int p) {
    const maille::Vec3 x = sim.state().x()[std::size_t(p)];
    return std::array<double, 3>{double(x.x), double(x.y), double(x.z)};
  };
  // Only the steps are timed; the meter reads the state between them.
  using clock = std::chrono::steady_clock;
  clock::duration wall{};
  std::uint64_t done = 0;
  for (; done < steps; ++done) {
    const auto t0 = clock::now();
    const bool ok = sim.step();
    wall += clock::now() - t0;
    if (!ok) {
      meter.fail("Maille blow-up: " + sim.blow_up()->module);
      break;
    }
    if (!meter.sample(get)) break;
  }
  if (done == steps && !sim.check_energy()) meter.fail("Maille energy runaway");
  RunResult r =
      meter.finish(step, double(done) * step, std::chrono::duration<double>(wall).count());
  // Where the step's time went: the link forces and the obstacle, in ns per particle-step.
  const double pps = double(done) * double(s.particles());
  for (const auto& st : sim.profile().stages())
    if (pps > 0 && (st.name == "link_forces" || st.name == "obstacle:sphere")) {
      char buf[96];
      std::snprintf(buf, sizeof buf, " %s=%.0fns/pps", st.name.c_str(), st.total_ns / pps);
      r.detail += buf;
    }
  return r;
}

}  // namespace peer
