// Obstacles (Theme 2), the geometric method: a geometric fixed point (a canonical shape placed
// by an affine map, shapes.hpp) pushes the free points of some groups out of it with a
// thresholded spring-damper acting on the penetration vector.
//
// Per particle, as the brief describes: x and v go into the canonical frame through M_i; the
// shape's distance function gives the canonical penetration vector d (zero outside); the force
// k d - z (v_c . n) n is computed there and comes back through M_d. Under a uniform scale s this
// is k times the world penetration (a resting particle sinks m g / k); under a non-uniform
// scale M_d bends it off the surface normal, so `normal = "world"` offers the variant along the
// world normal with the world depth. Far particles cost one bounding-sphere test.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "maille/model.hpp"
#include "maille/shapes.hpp"
#include "maille/stage.hpp"

namespace maille {

struct GeometricObstacle {
  std::string name = "obstacle";
  ShapeKind shape = ShapeKind::sphere;
  Real top = Real(0.5);   // cone: top radius / bottom radius, in [0, 1]
  Real tube = Real(0.3);  // torus: tube radius / major radius, in (0, 1]
  shapes::Affine place;   // canonical -> world
  Real stiffness = 2000;  // k, N/m
  Real damping = 1;       // z, N.s/m (along the normal)
  bool world_normal =
      false;  // false: the brief's mapping through M_d; true: along the world normal
  std::vector<std::string> collides_with;  // groups; empty: every free point
};


// The stage "obstacle:NAME" (Phase::forces). Counters obstacle_NAME_contacts, gauge
// obstacle_NAME_depth (deepest world penetration, m). Throws std::invalid_argument for unknown
// groups or groups without free points.
std::unique_ptr<Stage> make_geometric_obstacle_stage(const Model& m, const GeometricObstacle& o);

}  // namespace maille
