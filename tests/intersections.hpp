// Counts pairs of intersecting triangles that share no vertex: the witness of cloth passing
// through itself. An edge of one triangle crossing the other (segment-triangle test, Moller-
// Trumbore) detects every transversal intersection of two triangles; boxes prune far pairs.
#pragma once

#include <algorithm>
#include <array>
#include <cstdint>
#include <span>
#include <vector>

#include "maille/vec3.hpp"

namespace maille::test {

inline bool segment_hits_triangle(const Vec3& p, const Vec3& q, const Vec3& a, const Vec3& b,
                                  const Vec3& c) {
  const Vec3 d = q - p, e1 = b - a, e2 = c - a;
  const Vec3 h = cross(d, e2);
  const Real det = dot(e1, h);
  if (std::abs(det) < Real(1e-18)) return false;  // parallel: not a transversal crossing
  const Real inv = 1 / det;
  const Vec3 s = p - a;
  const Real u = dot(s, h) * inv;
  if (u < 0 || u > 1) return false;
  const Vec3 qv = cross(s, e1);
  const Real v = dot(d, qv) * inv;
  if (v < 0 || u + v > 1) return false;
  const Real t = dot(e2, qv) * inv;
  return t >= 0 && t <= 1;
}

inline std::size_t count_self_intersections(std::span<const Vec3> x,
                                            std::span<const std::array<std::uint32_t, 3>> tris) {
  struct Box {
    Vec3 lo, hi;
  };
  std::vector<Box> boxes(tris.size());
  for (std::size_t t = 0; t < tris.size(); ++t) {
    const auto [a, b, c] = tris[t];
    boxes[t] = {{std::min({x[a].x, x[b].x, x[c].x}), std::min({x[a].y, x[b].y, x[c].y}),
                 std::min({x[a].z, x[b].z, x[c].z})},
                {std::max({x[a].x, x[b].x, x[c].x}), std::max({x[a].y, x[b].y, x[c].y}),
                 std::max({x[a].z, x[b].z, x[c].z})}};
  }
  std::size_t count = 0;
  for (std::size_t s = 0; s < tris.size(); ++s)
    for (std::size_t t = s + 1; t < tris.size(); ++t) {
      const Box &p = boxes[s], &q = boxes[t];
      if (p.hi.x < q.lo.x || q.hi.x < p.lo.x || p.hi.y < q.lo.y || q.hi.y < p.lo.y ||
          p.hi.z < q.lo.z || q.hi.z < p.lo.z)
        continue;
      const auto& u = tris[s];
      const auto& w = tris[t];
      bool shared = false;
      for (auto i : u)
        for (auto j : w) shared |= i == j;
      if (shared) continue;
      bool hit = false;
      for (int e = 0; e < 3 && !hit; ++e) {
        hit |= segment_hits_triangle(x[u[e]], x[u[(e + 1) % 3]], x[w[0]], x[w[1]], x[w[2]]);
        hit |= segment_hits_triangle(x[w[e]], x[w[(e + 1) % 3]], x[u[0]], x[u[1]], x[u[2]]);
      }
      count += hit;
    }
  return count;
}

}  // namespace maille::test
