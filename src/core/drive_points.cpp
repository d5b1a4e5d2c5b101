#include "stages.hpp"

namespace maille::stages {

// Driven fixed points follow their path: position and velocity (the velocity matters to
// dampers attached to them). Run before the forces of a step and after its integration.
void drive(const Model& m, State& s, double t) {
  auto x = s.x();
  auto v = s.v();
  for (const auto& d : m.drives) {
    x[d.point] = d.path.position(t);
    v[d.point] = d.path.velocity(t);
  }
}

}  // namespace maille::stages
