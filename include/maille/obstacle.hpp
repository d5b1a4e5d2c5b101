// Obstacles: fixed or scripted geometry that free points collide with, by one of three
// methods chosen per obstacle (`[[obstacle]] method = ...` in scenes, docs/scene-format.md):
//
//   geometric    a geometric fixed point: x and v go into the shape's canonical frame through
//                M_i, the canonical distance function gives the penetration vector d, the
//                thresholded spring-damper k d - z (v_c . n) n acts there and comes back through
//                M_d (a conditional link on a non-Euclidean distance). Under a
//                uniform scale a resting particle sinks m g / k; under a non-uniform one M_d
//                bends the force off the surface normal, so `normal = "world"` acts along the
//                world normal with the world depth instead. Phase::forces.
//   facets       inverse dynamics on a triangle mesh ("par dynamique inverse"): the
//                segment P -> Q the particle will travel this step is tested against the facets
//                (N.AP > eps, N.PQ < 0, u <= 1, M inside); on a hit the force and velocity are
//                rewritten with dissipation alpha and friction beta (docs/obstacles.md derives
//                what they mean). Phase::response: after every force, before integration.
//   conditional  fixed points sampled on the surface (spacing tied to the threshold), each with
//                a conditional spring-damper (the `conditional` link's law) to the free points
//                that come closer than `threshold`, found through a grid of the samples.
//
// An obstacle may move by a scripted rigid motion (rotate, translate, oscillate); every method
// uses the velocity relative to the obstacle's surface.
#pragma once

#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "maille/mesh.hpp"
#include "maille/model.hpp"
#include "maille/shapes.hpp"
#include "maille/stage.hpp"

namespace maille {

enum class ObstacleMethod : std::uint8_t { geometric, facets, conditional };
template <>
struct NameTable<ObstacleMethod> {
  static constexpr std::string_view what = "obstacle method";
  static constexpr std::array<Name<ObstacleMethod>, 3> names{{
      {ObstacleMethod::geometric, "geometric", "a geometric fixed point: canonical distance"},
      {ObstacleMethod::facets, "facets", "inverse dynamics on a triangle mesh"},
      {ObstacleMethod::conditional, "conditional", "conditional links to surface samples"},
  }};
};

// Below this sliding speed an obstacle's friction turns viscous (as self-collision's), m/s.
inline constexpr Real kObstacleSlip = Real(1e-3);

// A rigid scripted motion applied on top of the obstacle's placement: a point x of the placed
// obstacle is at R(t) (x - center) + center + offset(t).
struct ObstacleMotion {
  enum class Kind : std::uint8_t {
    none,
    rotate,     // about the line through `center` along `axis`, `frequency` turns per second
    translate,  // offset(t) = velocity t
    oscillate,  // offset(t) = amplitude (sin(2 pi f t + phase) - sin(phase))
  };
  Kind kind = Kind::none;
  Vec3 axis{0, 1, 0};
  Vec3 center{};
  Vec3 velocity{};
  Vec3 amplitude{};
  Real frequency = 0;
  Real phase = 0;

  // The placement at time t (the base placement moved rigidly).
  shapes::Affine at(const shapes::Affine& base, double t) const;
  // Velocity of the obstacle's material point that is at world position x at time t.
  Vec3 velocity_at(const Vec3& x, double t) const;
  // The same field as a twist (devices evaluate it per point): velocity_at(x, t) = linear +
  // spin x (x - center), up to rounding.
  struct Twist {
    Vec3 linear, spin, center;
  };
  Twist twist(double t) const;
  bool moves() const { return kind != Kind::none; }
};

// The paths a scene names (motion = { path = "..." }); `none` is no path.
template <>
struct NameTable<ObstacleMotion::Kind> {
  static constexpr std::string_view what = "motion path";
  static constexpr std::array<Name<ObstacleMotion::Kind>, 3> names{{
      {ObstacleMotion::Kind::rotate, "rotate", "about an axis, `frequency` turns per second"},
      {ObstacleMotion::Kind::translate, "translate", "at a constant velocity"},
      {ObstacleMotion::Kind::oscillate, "oscillate", "amplitude sin(2 pi f t + phase)"},
  }};
};

struct Obstacle {
  std::string name = "obstacle";
  ObstacleMethod method = ObstacleMethod::geometric;
  ShapeKind shape{};  // a row of the shape table (shapes.hpp): the first, the sphere
  // The shape's parameter if it has one (a cone's `top`, a torus's `tube`: its ShapeParameter
  // gives the range); unset, the shape's default.
  std::optional<Real> shape_parameter;
  // A mesh file instead of a canonical shape (facets, conditional): the mesh in its own frame,
  // placed by `place` like a shape. Null: the canonical shape (tessellated where needed).
  std::shared_ptr<const TriMesh> mesh;
  std::string mesh_file;      // for messages and the viewer
  int resolution = 48;        // segments around curved canonical shapes (facets, drawing)
  shapes::Affine place;       // canonical (or mesh) frame -> world, at t = 0
  ObstacleMotion motion;      // on top of `place`
  Real stiffness = 2000;      // k, N/m (geometric, conditional)
  Real damping = 1;           // z, N.s/m (geometric, conditional), along the normal
  bool world_normal = false;  // geometric: false, the canonical mapping; true: world normal
  // geometric: Coulomb coefficient mu. The tangential force mu |F_n| opposes the sliding
  // velocity relative to the surface, viscous below kObstacleSlip (no chatter at rest);
  // implicit solvers lag |F_n| and the normal at the step's start.
  Real friction = 0;
  Real threshold = Real(0.02);  // conditional: contact distance of the sampled points, m
  Real alpha = Real(0.8);       // facets: dissipation in [0, 1] (normal restitution)
  Real beta = Real(0.3);        // facets: friction in [0, 1] (Coulomb coefficient)
  Real epsilon = Real(1e-6);    // facets: the tolerance eps (m): "above the facet" means N.AP > eps
  std::vector<std::string> collides_with;  // groups; empty: every free point
};

template <class S>
struct StageKey;  // stage_keys.hpp

// [[obstacle]]'s keys, declared once (src/collision/obstacle/obstacle_keys.cpp), with the methods
// that use each: the scene reader's gate, `maille info` and docs/scene-format.md read them.
std::span<const StageKey<Obstacle>> obstacle_keys();

// The obstacle's surface as a mesh in its own frame (the file's, or the canonical shape
// tessellated at `resolution`).
TriMesh obstacle_mesh(const Obstacle& o);

// The free points of `collides_with` (every free point when empty). Throws
// std::invalid_argument naming the obstacle for an unknown group or when no free point is left.
std::vector<std::uint32_t> colliding_points(const Model& m, const Obstacle& o);

// The stage's name (kObstacleStagePrefix + NAME) and phase (facets rewrite the state after the
// forces: Phase::response; the others add forces), said once for the scene table, the stages,
// the drawn surfaces and the GPU registry's family entry.
inline constexpr std::string_view kObstacleStagePrefix = "obstacle:";
std::string obstacle_stage_name(const Obstacle& o);
Phase obstacle_phase(ObstacleMethod m);

// Checks the obstacle against the model without building its stage: the groups exist and hold a
// free point, a geometric obstacle has no mesh, a facet mesh has facets, the conditional
// sampling fits (the key at fault and the message; empty when valid). make_obstacle_stage
// relies on it.
StageProblem check_obstacle(const Model& m, const Obstacle& o);

// The stage "obstacle:NAME" for the obstacle's method. Counters per step (stats.csv):
//   obstacle_NAME_contacts  particles in contact this step
//   obstacle_NAME_depth     deepest penetration, m (gauge)
// and for facets: obstacle_NAME_hits (swept hits), _sticks, _slides, _facet_leaks (particles
// found inside a closed mesh and pushed out). Throws std::invalid_argument (see
// check_obstacle's message).
std::unique_ptr<Stage> make_obstacle_stage(const Model& m, const Obstacle& o);
// The same, one method each (make_obstacle_stage dispatches on o.method).
std::unique_ptr<Stage> make_geometric_obstacle_stage(const Model& m, const Obstacle& o);
std::unique_ptr<Stage> make_facet_obstacle_stage(const Model& m, const Obstacle& o);
std::unique_ptr<Stage> make_conditional_obstacle_stage(const Model& m, const Obstacle& o);

}  // namespace maille
