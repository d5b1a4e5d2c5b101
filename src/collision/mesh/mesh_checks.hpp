// Pieces shared by the OBJ and STL readers (private to src/collision/mesh): messages, strict
// numbers, and the checks every mesh read from a file must pass.
#pragma once

#include <cstddef>
#include <string>
#include <string_view>

#include "maille/mesh.hpp"

namespace maille::mesh_detail {

// Throws MeshError("NAME: WHAT"), or "NAME:LINE: WHAT" when line > 0.
[[noreturn]] void fail(const std::string& name, std::size_t line, const std::string& what);

// A token as it may be quoted in a message: at most 32 characters, bytes outside printable
// ASCII as \xNN (hostile files put anything there).
std::string quote(std::string_view token);

// A decimal number, strictly: [+-] (digits [. [digits]] | . digits) [(e|E) [+-] digits], or
// nan / inf / infinity in any case (read, so that they are reported as such, not as words).
// (The grammar is the part tinyobjloader's number parser agreed with, when OBJ text also went
// through it: files keep their meaning.) Hexadecimal and trailing characters are not numbers.
enum class Number { ok, not_a_number, out_of_range };
Number parse_number(std::string_view token, double& value);

// Empty when x is a usable coordinate, else what is wrong with it: "NaN or infinite coordinate"
// or "coordinate beyond 1e+15" (mesh_limits::max_coordinate).
std::string coordinate_problem(double x);

// The first triangle whose area is zero, or below mesh_limits::min_relative_area times the
// squared diagonal of the vertices' bounding box; triangles.size() when there is none.
// Indices must be in range (the readers check them first).
std::size_t first_zero_area(const TriMesh& mesh);

// Content sniffing for read_mesh (stl_reader.cpp): a binary STL's size is exactly 84 + 50 n,
// n from its header; an ASCII STL starts with "solid" and has a facet or an endsolid.
bool looks_like_binary_stl(std::string_view bytes);
bool looks_like_ascii_stl(std::string_view bytes);

}  // namespace maille::mesh_detail
