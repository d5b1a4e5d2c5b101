// Geometric fixed points and geometric contacts, as bricks.
//
// A geometric fixed point is a fixed point that carries a canonical shape and the affine maps
// that place it (M_d, its inverse M_i, a translation; shapes.hpp). It has no velocity and takes
// no force, so it lives in its own pool (Model::geometric_points) beside the material points
// rather than as a point kind with dead rows. A geometric contact links one geometric fixed point
// to one free mass: the mass's position and velocity go into the canonical frame through M_i, the
// shape's distance function gives the penetration vector for the canonical threshold 1, a
// thresholded spring-damper acts on it there, and the force comes back through M_d into the
// mass's force buffer (the canonical-frame algorithm, step by step). `[[obstacle]] method =
// "geometric"` is one geometric point and its contacts with every colliding point, with a cull.
#pragma once

#include <array>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "maille/names.hpp"
#include "maille/shapes.hpp"
#include "maille/stage.hpp"

namespace maille {

// How a geometric contact pushes (scene key `normal` of [[obstacle]] and [[geometric_contact]]).
enum class ContactNormal : std::uint8_t { canonical, world };
template <>
struct NameTable<ContactNormal> {
  static constexpr std::string_view what = "contact normal";
  static constexpr std::array<Name<ContactNormal>, 2> names{{
      {ContactNormal::canonical, "canonical",
       "the canonical mapping: k times the world image of the canonical penetration"},
      {ContactNormal::world, "world", "along the world normal with the world depth"},
  }};
};

struct Model;

struct GeometricPoint {
  std::string name;
  ShapeKind shape{};                    // a row of the shape table (shapes.hpp): the sphere
  std::optional<Real> shape_parameter;  // as Obstacle's: unset, the shape's default
  shapes::Affine place;
};

struct GeometricContact {
  std::uint32_t point = 0;      // a free material point
  std::uint32_t geometric = 0;  // index in Model::geometric_points
  Real stiffness = 0;           // k, N/m (canonical: through M_d, k times the world penetration)
  Real damping = 0;             // z, N.s/m along the normal
  bool world_normal = false;    // along the world normal with the world depth (see obstacle.hpp)
};

// The contact law, written once for the bricks and the geometric obstacle. `v` is the mass's
// velocity relative to the shape's surface. Returns the force on the mass (zero outside) and
// sets `depth` to the world penetration (0 outside) and, when `normal` is given and the mass is
// inside, *normal to the unit world normal there (implicit solvers' stiffness k n n^T: through
// M_d the world stiffness is k whatever the scale, see GeometricObstacleStage).
Vec3 geometric_contact_force(const GeometricPoint& g, const shapes::Affine& place, const Vec3& x,
                             const Vec3& v, Real stiffness, Real damping, bool world_normal,
                             Real& depth, Vec3* normal = nullptr);

// The stage "geometric_contacts" that evaluates the model's geometric contact bricks
// (Phase::forces). Counters geometric_contacts_active, gauge geometric_contacts_depth.
// The stage's name and phase, said once (the scene reader's StageSpec and the stage).
inline constexpr StageInfo kGeometricContactStage{"geometric_contacts", Phase::forces};
std::unique_ptr<Stage> make_geometric_contact_stage(const Model& m,
                                                    std::vector<GeometricContact> contacts);

}  // namespace maille
