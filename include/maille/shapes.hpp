// Canonical shapes for geometric fixed points and obstacles: pure distance functions
// in the shape's canonical frame, and the affine map (direct M_d, inverse M_i) that places a
// shape in the world.
//
// Canonical shapes, all of unit size:
//   sphere      radius 1 about the origin (the Euclidean norm)
//   cube        [-1, 1]^3 (the max norm)
//   cylinder    axis y, radius 1, from y = -1 to 1, with its caps
//   cone        a frustum along y: radius 1 at y = -1, radius `top` (in [0, 1]) at y = 1, capped
//   torus       about the y axis, major radius 1, tube radius `tube` (in (0, 1])
//   capsule     the segment y in [-1, 1] grown by 1
//   half_space  y <= 0 (the plane y = 0, normal +y)
//
// Each returns the signed distance (negative inside) and the outward unit normal of the
// closest surface point: a point inside is moved to the surface by -distance * normal (the
// penetration vector). Results are defined everywhere: where the closest point is not unique
// (the centre of a sphere, the axis of a cylinder, the diagonal of a cube), the normal follows a
// fixed rule, documented per shape: +y first, then +x.
#pragma once

#include <cstdint>
#include <string_view>

#include "maille/mat3.hpp"
#include "maille/names.hpp"
#include "maille/vec3.hpp"

namespace maille {

// The canonical shapes by name (scene files: shape = "..."). `plane` is the half-space for the
// geometric method and the square [-1, 1] x {0} x [-1, 1] when tessellated.
enum class ShapeKind : std::uint8_t { sphere, cube, cylinder, cone, torus, capsule, plane };
template <>
struct NameTable<ShapeKind> {
  static constexpr std::string_view what = "shape";
  static constexpr std::array<Name<ShapeKind>, 7> names{{
      {ShapeKind::sphere, "sphere", "radius 1"},
      {ShapeKind::cube, "cube", "[-1, 1]^3"},
      {ShapeKind::cylinder, "cylinder", "along y, radius 1, y from -1 to 1, capped"},
      {ShapeKind::cone, "cone", "a frustum along y: radius 1 at y = -1, `top` at y = 1"},
      {ShapeKind::torus, "torus", "about y, major radius 1, tube radius `tube`"},
      {ShapeKind::capsule, "capsule", "the segment y in [-1, 1] grown by 1"},
      {ShapeKind::plane, "plane", "the half-space y <= 0 (tessellated: the unit square)"},
  }};
};

}  // namespace maille

namespace maille::shapes {

struct Distance {
  Real signed_distance = 0;  // m (canonical units): < 0 inside
  Vec3 normal{0, 1, 0};      // outward unit normal at the closest surface point
  bool inside() const { return signed_distance < 0; }
  Vec3 penetration() const { return inside() ? normal * (-signed_distance) : Vec3{}; }
};

Distance sphere(const Vec3& p);
Distance cube(const Vec3& p);
Distance cylinder(const Vec3& p);
Distance cone(const Vec3& p, Real top);
Distance torus(const Vec3& p, Real tube);
Distance capsule(const Vec3& p);
Distance half_space(const Vec3& p);

// x_world = M_d x_canonical + t, built from a position, rotations in degrees about x, then y,
// then z (world axes: R = Rz Ry Rx) and a per-axis scale (S first): M_d = R S. The inverse is
// kept beside it (M_i = S^-1 R^T), so the two stay consistent.
struct Affine {
  Mat3 direct = Mat3::identity();   // M_d
  Mat3 inverse = Mat3::identity();  // M_i
  Vec3 translation{};

  static Affine from(const Vec3& position, const Vec3& rotation_degrees, const Vec3& scale);
  Vec3 to_world(const Vec3& c) const { return direct * c + translation; }
  Vec3 to_canonical(const Vec3& w) const { return inverse * (w - translation); }
  Vec3 vector_to_world(const Vec3& c) const { return direct * c; }
  Vec3 vector_to_canonical(const Vec3& w) const { return inverse * w; }
  // A canonical normal as a world normal (inverse transpose), unit length.
  Vec3 normal_to_world(const Vec3& n) const;
  // This placement moved rigidly: x -> R (x - center) + center + offset (R a rotation).
  Affine moved(const Mat3& R, const Vec3& center, const Vec3& offset) const;
};

// The rotation by `angle` (rad) about the unit vector `axis` (Rodrigues).
Mat3 rotation(const Vec3& axis, double angle);

// The distance function of a shape kind (top: cone, tube: torus).
Distance canonical(ShapeKind s, const Vec3& p, Real top, Real tube);

}  // namespace maille::shapes
