// Small model factories shared by the tests.
#pragma once

#include <fenv.h>

#include <cmath>
#include <numbers>

#include <stdexcept>
#include <string>

#include "maille/link_registry.hpp"
#include "maille/links/damper.hpp"
#include "maille/links/spring.hpp"
#include "maille/links/spring_damper.hpp"
#include "maille/scene.hpp"
#include "maille/simulator.hpp"
#include "maille/stage_registry.hpp"

namespace maille::test {

// Turns floating-point traps off in this scope (the physics tests run with FE_INVALID,
// FE_DIVBYZERO and FE_OVERFLOW trapped, tests/physics/fp_traps.cpp), for runs that blow up on
// purpose; restores the traps that were on, with the flags raised meanwhile cleared. Applies to
// the calling thread: run such tests on one thread.
class FpTrapsOff {
 public:
  FpTrapsOff() : enabled_(fedisableexcept(FE_ALL_EXCEPT)) {}
  ~FpTrapsOff() {
    feclearexcept(FE_ALL_EXCEPT);
    if (enabled_ > 0) feenableexcept(enabled_);
  }
  FpTrapsOff(const FpTrapsOff&) = delete;
  FpTrapsOff& operator=(const FpTrapsOff&) = delete;

 private:
  int enabled_;
};

// A mass m on a spring-damper (k, z, rest L) to a fixed point at the origin, displaced by A
// along x; no gravity. u = x - L obeys u'' = -(k/m) u - (z/m) u'.
inline Model oscillator(Real m, Real k, Real z, Real L, Real A) {
  Model model;
  model.fields.gravity = {0, 0, 0};
  const auto anchor = model.points.add(PointKind::fixed, 1, {0, 0, 0});
  const auto bob = model.points.add(PointKind::free, m, {L + A, 0, 0});
  if (z == 0)
    model.links.pool<Spring>().add({anchor, bob}, {k, L});
  else
    model.links.pool<SpringDamper>().add({anchor, bob}, {k, L, z});
  return model;
}

inline SimulationSettings settings(double h, const char* integrator = "leapfrog") {
  SimulationSettings s;
  s.step = h;
  s.integrator = integrator;
  s.publish_every = 1 << 30;
  s.sample_every = 1 << 30;
  s.threads = 1;
  return s;
}

// Times at which u = x - L crosses zero upwards, linearly interpolated between steps.
inline std::vector<double> upward_crossings(Simulator& sim, std::uint32_t point, Real L,
                                            std::uint64_t steps) {
  std::vector<double> t;
  double prev = sim.state().x()[point].x - L, prev_t = sim.state().time;
  for (std::uint64_t i = 0; i < steps; ++i) {
    sim.step();
    const double u = sim.state().x()[point].x - L, now = sim.state().time;
    if (prev < 0 && u >= 0) t.push_back(prev_t + (now - prev_t) * (-prev) / (u - prev));
    prev = u;
    prev_t = now;
  }
  return t;
}

inline double mean_period(const std::vector<double>& crossings) {
  return (crossings.back() - crossings.front()) / double(crossings.size() - 1);
}

// A scene from its text with the built-in link kinds and stage tables; a parse error throws
// with its file:line:column message.
inline Scene scene_from_text(const std::string& text, const std::string& file = "test.toml") {
  static const LinkKindRegistry kinds = LinkKindRegistry::with_builtins();
  static const StageRegistry stages = StageRegistry::with_builtins();
  auto s = parse_scene(text, file, kinds, stages);
  if (!s) throw std::runtime_error(s.error().to_string());
  return std::move(s.value());
}

}  // namespace maille::test
