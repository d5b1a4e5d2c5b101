// Canonical shapes for geometric fixed points and obstacles: pure distance functions in the
// shape's canonical frame, and the affine map (direct M_d, inverse M_i) that places a shape in
// the world.
//
// The shapes, all of unit size, are the rows of one table (src/collision/shapes/shape_table.cpp:
// name, parameter, mesh, extents); their distance functions are the shared law's
// (include/maille/detail/obstacle_laws.glsl), written once for the CPU and the GPU. Each returns
// the signed distance (negative inside) and the outward unit normal of the closest surface point:
// a point inside is moved to the surface by -distance * normal (the penetration vector). Results
// are defined everywhere: where the closest point is not unique (the centre of a sphere, the axis
// of a cylinder, the diagonal of a cube), the normal follows a fixed rule, written beside each
// distance function: +y first, then +x.
#pragma once

#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <string_view>

#include "maille/link_kind.hpp"
#include "maille/mat3.hpp"
#include "maille/vec3.hpp"

namespace maille {

struct TriMesh;  // mesh.hpp

// A canonical shape: its row of the shape table (src/collision/shapes/shape_table.cpp, one row
// per shape), which is also its kShape* number in include/maille/detail/obstacle_laws.glsl.
// Scene files name it (shape = "torus"): parse_shape, shape_kind and to_string go between the
// two. The default value is the first row, the sphere.
enum class ShapeKind : std::uint8_t {};

// A shape's one parameter (a cone's `top`, a torus's `tube`): a number read from the scene key
// of that name on [[obstacle]] and [[geometric_point]] (include/maille/shape_keys.hpp declares
// the keys from these fields), checked against the bound, then lo <= value <= hi.
struct ShapeParameter {
  std::string_view key;        // the scene key
  Real fallback = 0;           // its default
  Bound bound = Bound::any;    // > 0, >= 0 or any
  Real lo = 0, hi = 0;         // its range
  std::string_view range_doc;  // the range as the docs write it: "(0, 1]"
  std::string_view doc;        // the key's one line of docs: "torus only: ..."
  std::string_view refusal;    // the message for the key on another shape
};

// One row of the shape table. The distance function is the shared law's (obstacle_laws.glsl's
// canonical_distance, by the row's number); the row gives the rest, from the parameter p
// (ignored by a shape that has none).
struct ShapeRow {
  std::string_view name;  // as written in scene files
  std::string_view doc;   // one line, for docs and help
  int number = 0;         // its kShape* constant (the table checks it is the row's index)
  std::optional<ShapeParameter> parameter{};
  // The shape tessellated (mesh.hpp's tessellate, which checks n against min_resolution and p
  // against the parameter's range first): about n segments around curved directions.
  TriMesh (*mesh)(int n, Real p) = nullptr;
  int min_resolution = 3;
  // The radius of a canonical sphere about the origin holding the shape (infinite: unbounded).
  Real (*reach)(Real p) = nullptr;
  // The thinnest canonical extent (infinite: none), a lower bound of the shape's thickness.
  Real (*thinnest)(Real p) = nullptr;
};

// At most this many shapes have a parameter (shape_keys.hpp declares their keys from as many
// slots; the table checks it).
inline constexpr std::size_t kMaxShapeParameters = 8;

// The shape table, in kShape* order (src/collision/shapes/shape_table.cpp).
std::span<const ShapeRow> shape_table();
// A shape's row; an out-of-range value is a programming error (std::logic_error).
const ShapeRow& shape_row(ShapeKind s);
// The shape named `name` in scene files, or nullopt.
std::optional<ShapeKind> parse_shape(std::string_view name);
// The same for code that names a shape it knows (shape_kind("torus")): an unknown name throws
// std::invalid_argument.
ShapeKind shape_kind(std::string_view name);
std::string_view to_string(ShapeKind s);
// Every shape's name, in table order (the scene's choices), and as the list messages show it.
std::span<const std::string_view> shape_names();
std::string shape_name_list(std::string_view separator = ", ");
// A shape's parameter: `p` when given, else the shape's default (0 for a shape without one).
Real shape_parameter(ShapeKind s, std::optional<Real> p);

}  // namespace maille

namespace maille::shapes {

struct Distance {
  Real signed_distance = 0;  // m (canonical units): < 0 inside
  Vec3 normal{0, 1, 0};      // outward unit normal at the closest surface point
  bool inside() const { return signed_distance < 0; }
  Vec3 penetration() const { return inside() ? normal * (-signed_distance) : Vec3{}; }
};

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

// A shape's distance function (the shared law's canonical_distance) with its parameter (a
// cone's top, a torus's tube: the shape's default when not given; ignored by the others).
Distance canonical(ShapeKind s, const Vec3& p, std::optional<Real> parameter = {});

}  // namespace maille::shapes
