// What the renderer draws besides positions: the static topology of a model, flattened into the
// arrays the GPU reads. Built once per model (and again after a scene reload). GL-free.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "maille/mesh.hpp"
#include "maille/model.hpp"

namespace maille::render {

// How a point is drawn; the values are read by the point shader.
enum class PointStyle : std::uint32_t {
  hidden = 0,  // a free point of a cloth surface: the surface shows it
  free = 1,    // a mass not on a surface (rope beads, lattice nodes)
  fixed = 2,   // inverse mass 0
  driven = 3,  // a fixed point on a scripted path
};

struct RenderTopology {
  std::uint32_t point_count = 0;
  // Links that always act (springs, dampers, spring-dampers), drawn as segments coloured by
  // strain |d| / rest - 1.
  std::vector<std::uint32_t> link_ends;       // [2 L] point indices a, b
  std::vector<float> link_rest;               // [L] m, > 0: the link's rest_length parameter when
                                              // its kind has one, else the initial distance
  std::vector<std::uint8_t> link_on_surface;  // [L] 1 when both ends are on a cloth surface
  // Conditional links (kinds with a `threshold` parameter): drawn only while active, as contacts.
  std::vector<std::uint32_t> contact_ends;  // [2 C]
  std::vector<float> contact_threshold;     // [C] m: active while the distance is below it
  std::vector<std::uint32_t> triangles;     // [3 T] cloth faces, counter-clockwise
  std::vector<std::uint32_t> point_style;   // [n] PointStyle
  float point_radius = 0.01f;               // m: drawn size of a point, from the link lengths
};

RenderTopology make_topology(const Model& model);

// Indices of the contacts active at `positions` (distance below the threshold), appended to
// `active` as pairs of point indices. Positions must hold topology.point_count points.
void active_contacts(const RenderTopology& topology, std::span<const Vec3> positions,
                     std::vector<std::uint32_t>& active);

// Area-weighted vertex normals of the surface at `positions` (unit vectors; zero for points not
// on the surface), written to `normals` as 3 floats per point.
void surface_normals(const RenderTopology& topology, std::span<const Vec3> positions,
                     std::vector<float>& normals);

// A solid's mesh (an obstacle's) as the solid pass draws it: three vertices per triangle, 6
// floats each (position, then unit normal), in the mesh's own frame. A corner's normal is the
// area-weighted sum of the faces around its vertex that turn by less than `crease_degrees` from
// its own face: a sphere looks round and a cube keeps its edges. Zero-area faces get a zero
// normal (the shader falls back to facing the eye).
std::vector<float> solid_vertices(const TriMesh& mesh, double crease_degrees = 40);

}  // namespace maille::render
