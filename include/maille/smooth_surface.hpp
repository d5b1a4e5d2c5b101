// Smooth surfaces drawn over the coarse physical mesh.
//
// A cloth simulated on a few hundred particles is dynamic but faceted. What is drawn (and
// exported) can be a smooth surface that passes through every particle:
//   grid cloth   (a group laid out as an (i, j) grid with faces: flags) bicubic Catmull-Rom
//                patches, one per grid cell, C1 across cells, with analytic normals; the rows
//                and columns beyond the border are extrapolated linearly (2 P0 - P1);
//   other faces  (membranes, lattice hulls, any triangle surface) curved PN triangles on
//                area-weighted vertex normals, with the normals of the cubic patch itself.
// The level of detail `lod` is the number of sub-segments per physical edge (1: the flat
// mesh's vertices, no new ones in between).
//
// The formulas live in include/maille/detail/smooth_math.glsl, compiled here in float and in
// the renderer's compute shader: this CPU evaluation is what `maille run --format obj --smooth`
// writes and the oracle the GPU evaluation is tested against. GL-free.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "maille/model.hpp"

namespace maille {

// The smooth mesh: vertices as 6 floats (position, unit normal), triangles counter-clockwise
// seen from the side the normals point to (the model's faces' orientation).
struct SmoothMesh {
  std::vector<float> vertices;           // [6 V]
  std::vector<std::uint32_t> triangles;  // [3 T]
  std::size_t vertex_count() const { return vertices.size() / 6; }
};

inline constexpr int kMaxSmoothLod = 16;

class SmoothSurface {
 public:
  // One grid cloth (a FaceGrid of the model): points first + j nx + i, i < nx, j < ny.
  struct Grid {
    std::uint32_t first = 0, nx = 0, ny = 0;
    std::uint32_t vertex_offset = 0;  // its first vertex in the smooth mesh (set per lod)
  };

  SmoothSurface() = default;
  // The grid cloths (find_face_grids, model.hpp) and the other faces; the model need not be
  // prepared.
  explicit SmoothSurface(const Model& model);

  bool empty() const { return grids_.empty() && others_.empty(); }
  const std::vector<Grid>& grids() const { return grids_; }
  const std::vector<std::uint32_t>& other_triangles() const { return others_; }  // [3 T]
  std::uint32_t point_count() const { return point_count_; }

  // Vertex counts at a level of detail: all grid vertices come first, then the PN triangles'.
  std::uint32_t grid_vertices(int lod) const;
  std::uint32_t vertex_count(int lod) const;
  static std::uint32_t vertices_per_triangle(int lod) {
    return std::uint32_t((lod + 1) * (lod + 2) / 2);
  }
  // The grids with their vertex offsets at this lod.
  std::vector<Grid> grids_at(int lod) const;
  // The triangles of the smooth mesh at this lod (indices into its vertices); they depend only
  // on the topology, not on the positions.
  std::vector<std::uint32_t> triangles(int lod) const;

  // Evaluates the surface at positions x (one per model point): out.vertices is filled (in the
  // order above) and out.triangles with triangles(lod). lod in [1, kMaxSmoothLod].
  void evaluate(std::span<const Vec3> x, int lod, SmoothMesh& out) const;

  // Points of one grid's patch at parameters (i + u, j + v), i in [0, nx - 2], u in [0, 1]:
  // position and the two tangents, for tests (finite differences) and callers that sample.
  void grid_point(std::span<const Vec3> x, const Grid& g, std::uint32_t i, std::uint32_t j, float u,
                  float v, Vec3& s, Vec3& su, Vec3& sv) const;

 private:
  std::vector<Grid> grids_;
  std::vector<std::uint32_t> others_;
  std::uint32_t point_count_ = 0;
};

// Area-weighted vertex normals of the given triangles at x (unit; zero for points on none), as
// 3 floats per point: the normals PN triangles bend to.
void vertex_normals(std::span<const std::uint32_t> triangles, std::span<const Vec3> x,
                    std::vector<float>& normals);

}  // namespace maille
