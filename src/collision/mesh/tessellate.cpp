// The canonical shapes as closed triangle meshes (tessellate: each shape's mesh is its row of the
// shape table, built from the pieces here: tessellation.hpp), and the icosphere.
//
// The solids of revolution (sphere, cylinder, cone, capsule, torus) are one algorithm: a
// profile polyline in the (r, y) half-plane, run counter-clockwise (r to the right, y up: the
// outward normal is the tangent turned clockwise, (dy, -dr)), swept about the y axis in `n`
// equal steps. A profile point with r == 0 is a single vertex on the axis (a pole, a cap's
// centre, a cone's apex); any other is a ring of n vertices (r cos phi, y, r sin phi). Each
// profile point is made once, so consecutive bands share their rings and the mesh is welded
// by construction. With phi increasing from +x towards +z, a band between points a and b
// (b after a along the profile) is
//
//     b_j ---- b_j+1        triangles (a_j, b_j, b_j+1) and (a_j, b_j+1, a_j+1):
//      |  \      |          counter-clockwise seen from outside; a pole A or B keeps
//     a_j ---- a_j+1        (A, b_j, b_j+1) or (a_j, B, a_j+1).
//
// Profile points are placed on the canonical surface; where a curve meets the axis or a cap,
// the end point is written exactly ((0, -1), (1, -1), ...) rather than computed (sin(pi) is not
// 0). Segments along the profile are about as long as those around (2 pi / n at radius 1).
#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>
#include <string>
#include <unordered_map>
#include <vector>

#include "maille/mesh.hpp"
#include "tessellation.hpp"

namespace maille {

namespace {
constexpr int kMaxResolution = 1024;
}  // namespace

namespace tessellation {

// The sweep described above.
TriMesh revolve(const std::vector<P2>& profile, int n, bool loop) {
  TriMesh mesh;
  std::vector<std::uint32_t> first(profile.size());  // each point's first vertex
  for (std::size_t i = 0; i < profile.size(); ++i) {
    first[i] = static_cast<std::uint32_t>(mesh.vertices.size());
    const P2 p = profile[i];
    if (p.r == 0) {
      mesh.vertices.push_back({0, Real(p.y), 0});
      continue;
    }
    for (int j = 0; j < n; ++j) {
      const double phi = 2 * kPi * j / n;
      mesh.vertices.push_back({Real(p.r * std::cos(phi)), Real(p.y), Real(p.r * std::sin(phi))});
    }
  }
  auto ring = [&](std::size_t i, int j) { return first[i] + static_cast<std::uint32_t>(j % n); };
  const std::size_t bands = loop ? profile.size() : profile.size() - 1;
  for (std::size_t i = 0; i < bands; ++i) {
    const std::size_t a = i, b = (i + 1) % profile.size();
    const bool a_pole = profile[a].r == 0, b_pole = profile[b].r == 0;
    for (int j = 0; j < n; ++j) {
      if (a_pole && b_pole) break;  // a profile segment on the axis sweeps nothing
      if (a_pole) {
        mesh.triangles.push_back({first[a], ring(b, j), ring(b, j + 1)});
      } else if (b_pole) {
        mesh.triangles.push_back({ring(a, j), first[b], ring(a, j + 1)});
      } else {
        mesh.triangles.push_back({ring(a, j), ring(b, j), ring(b, j + 1)});
        mesh.triangles.push_back({ring(a, j), ring(b, j + 1), ring(a, j + 1)});
      }
    }
  }
  return mesh;
}

// Six faces of k x k squares on [-1, 1]^3; grid points are keyed by their integer lattice
// coordinates, so edges and corners shared by faces are shared vertices. A face on axis a at
// side s spans axes u = a+1, v = a+2 (cyclic): e_u x e_v = e_a, so (00, 10, 11) faces +a and
// the order is reversed on the negative side.
TriMesh box_grid(int k) {
  TriMesh mesh;
  std::unordered_map<int, std::uint32_t> index;
  auto coord = [k](int i) { return i == k ? Real(1) : Real(-1 + 2.0 * i / k); };
  auto vertex = [&](int lattice[3]) {
    const int key = (lattice[0] * (k + 1) + lattice[1]) * (k + 1) + lattice[2];
    const auto [it, inserted] = index.try_emplace(key, std::uint32_t(mesh.vertices.size()));
    if (inserted)
      mesh.vertices.push_back({coord(lattice[0]), coord(lattice[1]), coord(lattice[2])});
    return it->second;
  };
  for (int a = 0; a < 3; ++a)
    for (int side = 0; side < 2; ++side) {
      const int u = (a + 1) % 3, v = (a + 2) % 3;
      for (int i = 0; i < k; ++i)
        for (int j = 0; j < k; ++j) {
          std::uint32_t q[2][2];
          for (int di = 0; di < 2; ++di)
            for (int dj = 0; dj < 2; ++dj) {
              int l[3];
              l[a] = side == 0 ? 0 : k;
              l[u] = i + di;
              l[v] = j + dj;
              q[di][dj] = vertex(l);
            }
          if (side == 1) {
            mesh.triangles.push_back({q[0][0], q[1][0], q[1][1]});
            mesh.triangles.push_back({q[0][0], q[1][1], q[0][1]});
          } else {
            mesh.triangles.push_back({q[0][0], q[1][1], q[1][0]});
            mesh.triangles.push_back({q[0][0], q[0][1], q[1][1]});
          }
        }
    }
  return mesh;
}

// k x k squares over [-1, 1]^2 at y = 0: rows along z (i), columns along x (j); e_z x e_x = +y,
// so (i j, i+1 j, i+1 j+1) faces up.
TriMesh square_grid(int k) {
  TriMesh mesh;
  auto coord = [k](int i) { return i == k ? Real(1) : Real(-1 + 2.0 * i / k); };
  for (int i = 0; i <= k; ++i)
    for (int j = 0; j <= k; ++j) mesh.vertices.push_back({coord(j), 0, coord(i)});
  auto at = [k](int i, int j) { return static_cast<std::uint32_t>(i * (k + 1) + j); };
  for (int i = 0; i < k; ++i)
    for (int j = 0; j < k; ++j) {
      mesh.triangles.push_back({at(i, j), at(i + 1, j), at(i + 1, j + 1)});
      mesh.triangles.push_back({at(i, j), at(i + 1, j + 1), at(i, j + 1)});
    }
  return mesh;
}

}  // namespace tessellation

TriMesh tessellate(ShapeKind shape, int resolution, std::optional<Real> parameter) {
  const ShapeRow& row = shape_row(shape);
  if (resolution < row.min_resolution || resolution > kMaxResolution)
    throw std::invalid_argument("tessellate: resolution " + std::to_string(resolution) + " for a " +
                                std::string(row.name) + " is outside [" +
                                std::to_string(row.min_resolution) + ", 1024]");
  const Real p = shape_parameter(shape, parameter);
  if (const auto& q = row.parameter) {
    const bool above = q->bound == Bound::positive ? p > q->lo : p >= q->lo;
    if (!(above && p <= q->hi))
      throw std::invalid_argument("tessellate: a " + std::string(row.name) + "'s " +
                                  std::string(q->key) + " must be in " + std::string(q->range_doc));
  }
  return row.mesh(resolution, p);
}

// Subdivision splits each triangle in four at its edge midpoints (one vertex per edge, found
// by the edge's sorted index pair) pushed out to the sphere; the children keep their parent's
// orientation. The icosahedron's faces are oriented outward by their own normal (it is convex).
TriMesh icosphere(int levels) {
  if (levels < 0 || levels > 8)
    throw std::invalid_argument("icosphere: levels " + std::to_string(levels) +
                                " is outside [0, 8]");
  const double g = (1 + std::sqrt(5.0)) / 2;
  const double raw[12][3] = {{-1, g, 0}, {1, g, 0}, {-1, -g, 0}, {1, -g, 0},
                             {0, -1, g}, {0, 1, g}, {0, -1, -g}, {0, 1, -g},
                             {g, 0, -1}, {g, 0, 1}, {-g, 0, -1}, {-g, 0, 1}};
  TriMesh mesh;
  for (const auto& p : raw) {
    const Vec3 v{Real(p[0]), Real(p[1]), Real(p[2])};
    mesh.vertices.push_back(v / norm(v));
  }
  const std::uint32_t faces[20][3] = {{0, 11, 5}, {0, 5, 1},  {0, 1, 7},   {0, 7, 10}, {0, 10, 11},
                                      {1, 5, 9},  {5, 11, 4}, {11, 10, 2}, {10, 7, 6}, {7, 1, 8},
                                      {3, 9, 4},  {3, 4, 2},  {3, 2, 6},   {3, 6, 8},  {3, 8, 9},
                                      {4, 9, 5},  {2, 4, 11}, {6, 2, 10},  {8, 6, 7},  {9, 8, 1}};
  for (const auto& f : faces) {
    const Vec3 a = mesh.vertices[f[0]], b = mesh.vertices[f[1]], c = mesh.vertices[f[2]];
    if (dot(cross(b - a, c - a), a + b + c) > 0)
      mesh.triangles.push_back({f[0], f[1], f[2]});
    else
      mesh.triangles.push_back({f[0], f[2], f[1]});
  }
  for (int level = 0; level < levels; ++level) {
    std::unordered_map<std::uint64_t, std::uint32_t> midpoint;
    auto mid = [&](std::uint32_t i, std::uint32_t j) {
      const std::uint64_t key = std::uint64_t(std::min(i, j)) << 32 | std::max(i, j);
      const auto [it, inserted] = midpoint.try_emplace(key, std::uint32_t(mesh.vertices.size()));
      if (inserted) {
        const Vec3 m = mesh.vertices[i] + mesh.vertices[j];
        mesh.vertices.push_back(m / norm(m));
      }
      return it->second;
    };
    std::vector<std::array<std::uint32_t, 3>> next;
    next.reserve(4 * mesh.triangles.size());
    for (const auto& t : mesh.triangles) {
      const std::uint32_t ab = mid(t[0], t[1]), bc = mid(t[1], t[2]), ca = mid(t[2], t[0]);
      next.push_back({t[0], ab, ca});
      next.push_back({t[1], bc, ab});
      next.push_back({t[2], ca, bc});
      next.push_back({ab, bc, ca});
    }
    mesh.triangles = std::move(next);
  }
  return mesh;
}

}  // namespace maille
