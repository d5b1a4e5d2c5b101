// Triangle meshes for obstacles: read from OBJ or STL files, or tessellated from the
// canonical shapes (shapes.hpp) at their canonical size. The facet stage (obstacle.hpp) and the
// renderer use them; a mesh is only geometry, in the frame it was read or made in.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

#include "maille/shapes.hpp"
#include "maille/vec3.hpp"

namespace maille {

struct TriMesh {
  std::vector<Vec3> vertices;
  // Vertex indices, counter-clockwise seen from outside: the face normal (b - a) x (c - a)
  // points out of closed meshes.
  std::vector<std::array<std::uint32_t, 3>> triangles;

  // Every edge is shared by exactly two triangles that run along it in opposite directions
  // (a closed, consistently oriented, manifold surface: it has an inside).
  bool closed() const;
  // Signed volume (divergence theorem): positive for a closed mesh oriented outwards.
  Real volume() const;
  Real area() const;
};

// What a mesh file may ask for. Beyond these the reader throws MeshError before allocating for
// them: a header or a count that claims more is refused, not trusted.
namespace mesh_limits {
inline constexpr std::size_t max_triangles = 10'000'000;
// Positions (and OBJ texture coordinates and normals, which are read and dropped).
inline constexpr std::size_t max_vertices = 3 * max_triangles;
// Vertices of one OBJ polygon: the reader's ear clipping is cubic in it.
inline constexpr std::size_t max_polygon_vertices = 256;
inline constexpr std::uintmax_t max_file_bytes = std::uintmax_t{1} << 30;  // 1 GiB
// Coordinates beyond this magnitude are refused: products of differences (areas, volumes) stay
// far from overflow, in float builds too.
inline constexpr Real max_coordinate = Real(1e15);
// A face whose area is below this fraction of the squared bounding-box diagonal is zero-area.
inline constexpr Real min_relative_area = Real(1e-12);
}  // namespace mesh_limits

// A mesh file that cannot be used. what() starts with the file name (and "FILE:LINE:" where a
// line is known) and says what is wrong: empty, truncated, not a number, NaN or infinite
// coordinate, index out of range, zero-area face, too many triangles.
class MeshError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// Reads an OBJ (one pass: polygons triangulated, groups merged) or an STL (ASCII or
// binary, told apart by content, not by extension) file. STL vertices that coincide exactly are
// welded, so that shared edges are shared indices. Throws MeshError.
TriMesh read_mesh(const std::string& path);
// The same from bytes in memory; `name` is used in messages (fuzzing, tests).
TriMesh parse_obj(std::string_view text, const std::string& name);
TriMesh parse_stl(std::string_view bytes, const std::string& name);
// Writes an ASCII OBJ (tests and tools; examples ship their meshes this way).
std::string to_obj(const TriMesh& mesh);

// A canonical shape as a closed mesh (the plane: the open square [-1, 1] x {0} x [-1, 1], normal
// +y), with about `resolution` segments around (and proportionally along) curved directions;
// `parameter`: the shape's parameter (shapes.hpp's ShapeParameter: a cone's top, a torus's
// tube), its default when not given. Vertices lie on the canonical surface. resolution:
// [3, 1024] (the plane's squares per side: [1, 1024]; the cube's squares per edge are
// resolution / 4, at least 1). Arguments out of range throw std::invalid_argument (a caller's
// error: scene values are checked where they are read).
TriMesh tessellate(ShapeKind shape, int resolution, std::optional<Real> parameter = {});
// A sphere by subdividing an icosahedron `levels` times (20 * 4^levels faces), vertices on the
// unit sphere. levels: [0, 8], else std::invalid_argument.
TriMesh icosphere(int levels);

}  // namespace maille
