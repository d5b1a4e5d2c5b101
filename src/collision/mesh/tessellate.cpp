// The canonical shapes as closed triangle meshes, and the icosphere.
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

namespace maille {

namespace {

constexpr double kPi = std::numbers::pi;
constexpr int kMaxResolution = 1024;

struct P2 {
  double r, y;
};

class Profile {
 public:
  explicit Profile(P2 start) : points_{start} {}
  // Straight to `end` in `count` equal steps (end exact).
  void line_to(P2 end, int count) {
    const P2 a = points_.back();
    for (int i = 1; i < count; ++i) {
      const double t = double(i) / count;
      points_.push_back({a.r + (end.r - a.r) * t, a.y + (end.y - a.y) * t});
    }
    points_.push_back(end);
  }
  // Along the circle (centre, radius) from the current angle to `to` (radians, increasing:
  // counter-clockwise) in `count` steps, ending exactly at `end`.
  void arc_to(P2 centre, double radius, double from, double to, P2 end, int count) {
    for (int i = 1; i < count; ++i) {
      const double a = from + (to - from) * i / count;
      points_.push_back({centre.r + radius * std::cos(a), centre.y + radius * std::sin(a)});
    }
    points_.push_back(end);
  }
  std::vector<P2>& points() { return points_; }

 private:
  std::vector<P2> points_;
};

// Segments for a length at the target spacing 2 pi / n: at least one.
int steps(double length, int n) {
  return std::max(1, static_cast<int>(std::ceil(length * n / (2 * kPi) - 1e-9)));
}

// The sweep described above. `loop`: the profile closes on itself (the torus).
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

TriMesh sphere(int n) {
  Profile p({0, -1});
  p.arc_to({0, 0}, 1, -kPi / 2, kPi / 2, {0, 1}, steps(kPi, n));
  return revolve(p.points(), n, false);
}

TriMesh cylinder(int n) {
  Profile p({0, -1});
  p.line_to({1, -1}, steps(1, n));
  p.line_to({1, 1}, steps(2, n));
  p.line_to({0, 1}, steps(1, n));
  return revolve(p.points(), n, false);
}

// A frustum; top == 0 ends at the apex (0, 1), which is a pole: still closed.
TriMesh cone(int n, double top) {
  Profile p({0, -1});
  p.line_to({1, -1}, steps(1, n));
  p.line_to({top, 1}, steps(std::hypot(2.0, 1 - top), n));
  if (top > 0) p.line_to({0, 1}, steps(top, n));
  return revolve(p.points(), n, false);
}

// A cylinder of radius 1 from y = -1 to 1 between two hemispheres (centres y = -1 and 1).
TriMesh capsule(int n) {
  Profile p({0, -2});
  p.arc_to({0, -1}, 1, -kPi / 2, 0, {1, -1}, steps(kPi / 2, n));
  p.line_to({1, 1}, steps(2, n));
  p.arc_to({0, 1}, 1, 0, kPi / 2, {0, 2}, steps(kPi / 2, n));
  return revolve(p.points(), n, false);
}

// The tube's circle about (1, 0), counter-clockwise from its outer point, as a closed loop;
// about as many segments around the tube as its circumference asks for, at least 3.
TriMesh torus(int n, double tube) {
  const int m = std::max(3, steps(2 * kPi * tube, n));
  std::vector<P2> loop;
  for (int i = 0; i < m; ++i) {
    const double a = 2 * kPi * i / m;
    // tube = 1 touches the axis (a horn torus): that point is a pole, exactly r = 0.
    const double r = 1 + tube * std::cos(a);
    loop.push_back({r < 1e-12 ? 0.0 : r, tube * std::sin(a)});
  }
  return revolve(loop, n, true);
}

// Six faces of k x k squares on [-1, 1]^3; grid points are keyed by their integer lattice
// coordinates, so edges and corners shared by faces are shared vertices. A face on axis a at
// side s spans axes u = a+1, v = a+2 (cyclic): e_u x e_v = e_a, so (00, 10, 11) faces +a and
// the order is reversed on the negative side.
TriMesh cube(int k) {
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
TriMesh plane(int k) {
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

}  // namespace

TriMesh tessellate(ShapeKind shape, int resolution, Real top, Real tube) {
  const int min_resolution = shape == ShapeKind::plane ? 1 : 3;
  if (resolution < min_resolution || resolution > kMaxResolution)
    throw std::invalid_argument("tessellate: resolution " + std::to_string(resolution) + " for a " +
                                std::string(to_string(shape)) + " is outside [" +
                                std::to_string(min_resolution) + ", 1024]");
  if (shape == ShapeKind::cone && !(top >= 0 && top <= 1))
    throw std::invalid_argument("tessellate: a cone's top radius must be in [0, 1]");
  if (shape == ShapeKind::torus && !(tube > 0 && tube <= 1))
    throw std::invalid_argument("tessellate: a torus's tube radius must be in (0, 1]");
  switch (shape) {
    case ShapeKind::sphere:
      return sphere(resolution);
    case ShapeKind::cube:
      return cube(std::max(1, resolution / 4));
    case ShapeKind::cylinder:
      return cylinder(resolution);
    case ShapeKind::cone:
      return cone(resolution, double(top));
    case ShapeKind::torus:
      return torus(resolution, double(tube));
    case ShapeKind::capsule:
      return capsule(resolution);
    case ShapeKind::plane:
      return plane(resolution);
  }
  throw std::invalid_argument("tessellate: unknown shape");
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
