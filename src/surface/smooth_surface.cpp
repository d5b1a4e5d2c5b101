// Smooth surfaces over the physical mesh (include/maille/smooth_surface.hpp): which faces are
// grid cloth and which are not, the smooth mesh's layout, and its evaluation on the CPU through
// the shared math of include/maille/detail/smooth_math.glsl.
#include "maille/smooth_surface.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace maille {

namespace glsl {

// Just enough of GLSL for smooth_math.glsl: a float vec3, its operators and built-ins.
struct vec3 {
  float x = 0, y = 0, z = 0;
};
inline vec3 operator+(vec3 a, vec3 b) {
  return {a.x + b.x, a.y + b.y, a.z + b.z};
}
inline vec3 operator-(vec3 a, vec3 b) {
  return {a.x - b.x, a.y - b.y, a.z - b.z};
}
inline vec3 operator*(vec3 a, float s) {
  return {a.x * s, a.y * s, a.z * s};
}
inline float dot(vec3 a, vec3 b) {
  return a.x * b.x + a.y * b.y + a.z * b.z;
}
inline vec3 cross(vec3 a, vec3 b) {
  return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}
inline float length(vec3 a) {
  return std::sqrt(dot(a, a));
}

#define MAILLE_SHARED inline
#define MAILLE_OUT(T) T&
#include "maille/detail/smooth_math.glsl"
#undef MAILLE_SHARED
#undef MAILLE_OUT

}  // namespace glsl

namespace {

glsl::vec3 to_glsl(const Vec3& v) {
  return {float(v.x), float(v.y), float(v.z)};
}
Vec3 from_glsl(const glsl::vec3& v) {
  return {Real(v.x), Real(v.y), Real(v.z)};
}

void push_vertex(std::vector<float>& out, const glsl::vec3& s, const glsl::vec3& n) {
  out.insert(out.end(), {s.x, s.y, s.z, n.x, n.y, n.z});
}

void check_lod(int lod) {
  if (lod < 1 || lod > kMaxSmoothLod)
    throw std::invalid_argument("smooth surface: level of detail " + std::to_string(lod) +
                                " out of [1, " + std::to_string(kMaxSmoothLod) + "]");
}

// Index of vertex (i, j), i + j <= lod, in a PN triangle's lattice: rows of j, each lod + 1 - j
// long.
std::uint32_t lattice_index(int i, int j, int lod) {
  return std::uint32_t(j * (lod + 1) - j * (j - 1) / 2 + i);
}

}  // namespace

SmoothSurface::SmoothSurface(const Model& model) : point_count_(model.points.size()) {
  // Grid cloths: the model's face grids (flags: the faces (p, p + 1, p + nx + 1) and
  // (p, p + nx + 1, p + nx) of every cell, counter-clockwise in (i, j), so the normal is
  // dS/du x dS/dv). Every other face is a PN triangle.
  std::vector<char> in_grid;
  for (const FaceGrid& g : find_face_grids(model, in_grid)) grids_.push_back({g.first, g.nx, g.ny});
  const auto& tris = model.surface.triangles;
  for (std::size_t f = 0; f < tris.size(); ++f)
    if (!in_grid[f]) others_.insert(others_.end(), {tris[f][0], tris[f][1], tris[f][2]});
}

std::uint32_t SmoothSurface::grid_vertices(int lod) const {
  std::uint32_t n = 0;
  for (const Grid& g : grids_)
    n += (std::uint32_t(lod) * (g.nx - 1) + 1) * (std::uint32_t(lod) * (g.ny - 1) + 1);
  return n;
}

std::uint32_t SmoothSurface::vertex_count(int lod) const {
  return grid_vertices(lod) + std::uint32_t(others_.size() / 3) * vertices_per_triangle(lod);
}

std::vector<SmoothSurface::Grid> SmoothSurface::grids_at(int lod) const {
  std::vector<Grid> out = grids_;
  std::uint32_t offset = 0;
  for (Grid& g : out) {
    g.vertex_offset = offset;
    offset += (std::uint32_t(lod) * (g.nx - 1) + 1) * (std::uint32_t(lod) * (g.ny - 1) + 1);
  }
  return out;
}

std::vector<std::uint32_t> SmoothSurface::triangles(int lod) const {
  check_lod(lod);
  std::vector<std::uint32_t> out;
  for (const Grid& g : grids_at(lod)) {
    const std::uint32_t cols = std::uint32_t(lod) * (g.nx - 1) + 1;
    const std::uint32_t rows = std::uint32_t(lod) * (g.ny - 1) + 1;
    for (std::uint32_t b = 0; b + 1 < rows; ++b)
      for (std::uint32_t a = 0; a + 1 < cols; ++a) {
        const std::uint32_t v00 = g.vertex_offset + b * cols + a, v10 = v00 + 1;
        const std::uint32_t v01 = v00 + cols, v11 = v01 + 1;
        out.insert(out.end(), {v00, v10, v11, v00, v11, v01});
      }
  }
  const std::uint32_t per = vertices_per_triangle(lod);
  std::uint32_t base = grid_vertices(lod);
  for (std::size_t t = 0; t < others_.size() / 3; ++t, base += per)
    for (int j = 0; j < lod; ++j)
      for (int i = 0; i + j < lod; ++i) {
        out.insert(out.end(), {base + lattice_index(i, j, lod), base + lattice_index(i + 1, j, lod),
                               base + lattice_index(i, j + 1, lod)});
        if (i + j + 1 < lod)
          out.insert(out.end(),
                     {base + lattice_index(i + 1, j, lod), base + lattice_index(i + 1, j + 1, lod),
                      base + lattice_index(i, j + 1, lod)});
      }
  return out;
}

void SmoothSurface::grid_point(std::span<const Vec3> x, const Grid& g, std::uint32_t i,
                               std::uint32_t j, float u, float v, Vec3& s, Vec3& su,
                               Vec3& sv) const {
  // The 4 x 4 control points around cell (i, j); beyond the border, linear extrapolation.
  auto at = [&](int a, int b) -> glsl::vec3 {
    const int nx = int(g.nx), ny = int(g.ny);
    auto fetch = [&](int c, int d) { return to_glsl(x[g.first + std::uint32_t(d * nx + c)]); };
    auto column = [&](int c, int d) {  // d may be -1 or ny
      if (d < 0) return fetch(c, 0) * 2.0f - fetch(c, 1);
      if (d >= ny) return fetch(c, ny - 1) * 2.0f - fetch(c, ny - 2);
      return fetch(c, d);
    };
    if (a < 0) return column(0, b) * 2.0f - column(1, b);
    if (a >= nx) return column(nx - 1, b) * 2.0f - column(nx - 2, b);
    return column(a, b);
  };
  glsl::vec3 p[16];
  for (int r = 0; r < 4; ++r)
    for (int c = 0; c < 4; ++c) p[4 * r + c] = at(int(i) - 1 + c, int(j) - 1 + r);
  glsl::vec3 gs, gu, gv;
  glsl::cr_patch(p, u, v, gs, gu, gv);
  s = from_glsl(gs), su = from_glsl(gu), sv = from_glsl(gv);
}

void SmoothSurface::evaluate(std::span<const Vec3> x, int lod, SmoothMesh& out) const {
  check_lod(lod);
  if (x.size() != point_count_)
    throw std::invalid_argument("smooth surface: " + std::to_string(x.size()) +
                                " positions for a model of " + std::to_string(point_count_));
  out.vertices.clear();
  out.vertices.reserve(std::size_t(vertex_count(lod)) * 6);
  const float step = 1.0f / float(lod);
  for (const Grid& g : grids_) {
    const std::uint32_t cols = std::uint32_t(lod) * (g.nx - 1) + 1;
    const std::uint32_t rows = std::uint32_t(lod) * (g.ny - 1) + 1;
    for (std::uint32_t b = 0; b < rows; ++b)
      for (std::uint32_t a = 0; a < cols; ++a) {
        // The last row and column are the end (t = 1) of the last cell.
        const std::uint32_t i = std::min(a / std::uint32_t(lod), g.nx - 2);
        const std::uint32_t j = std::min(b / std::uint32_t(lod), g.ny - 2);
        const float u = float(a - i * std::uint32_t(lod)) * step;
        const float v = float(b - j * std::uint32_t(lod)) * step;
        Vec3 s, su, sv;
        grid_point(x, g, i, j, u, v, s, su, sv);
        push_vertex(out.vertices, to_glsl(s), glsl::unit_normal(to_glsl(su), to_glsl(sv)));
      }
  }
  if (!others_.empty()) {
    std::vector<float> normals;
    vertex_normals(others_, x, normals);
    auto normal = [&](std::uint32_t p) {
      return glsl::vec3{normals[3 * p], normals[3 * p + 1], normals[3 * p + 2]};
    };
    for (std::size_t t = 0; t + 2 < others_.size(); t += 3) {
      const std::uint32_t a = others_[t], b = others_[t + 1], c = others_[t + 2];
      for (int j = 0; j <= lod; ++j)
        for (int i = 0; i + j <= lod; ++i) {
          glsl::vec3 s, sb, sc;
          glsl::pn_triangle(to_glsl(x[a]), to_glsl(x[b]), to_glsl(x[c]), normal(a), normal(b),
                            normal(c), float(i) * step, float(j) * step, s, sb, sc);
          push_vertex(out.vertices, s, glsl::unit_normal(sb, sc));
        }
    }
  }
  out.triangles = triangles(lod);
}

void vertex_normals(std::span<const std::uint32_t> triangles, std::span<const Vec3> x,
                    std::vector<float>& normals) {
  std::vector<Vec3> sum(x.size());
  for (std::size_t t = 0; t + 2 < triangles.size(); t += 3) {
    const std::uint32_t a = triangles[t], b = triangles[t + 1], c = triangles[t + 2];
    const Vec3 n = cross(x[b] - x[a], x[c] - x[a]);  // twice the area, along the normal
    sum[a] += n, sum[b] += n, sum[c] += n;
  }
  normals.assign(3 * x.size(), 0.0f);
  for (std::size_t p = 0; p < x.size(); ++p) {
    const Real l = norm(sum[p]);
    if (!(l > 0) || !std::isfinite(l)) continue;
    normals[3 * p] = float(sum[p].x / l);
    normals[3 * p + 1] = float(sum[p].y / l);
    normals[3 * p + 2] = float(sum[p].z / l);
  }
}

}  // namespace maille
