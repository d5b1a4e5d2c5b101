// TriMesh's own measures: closedness (an edge test), signed volume and area.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

#include "maille/mesh.hpp"

namespace maille {

// Closed and consistently oriented means: every directed edge a -> b appears exactly once, and
// so does its twin b -> a. Sorting the directed edges as 64-bit keys finds both in O(T log T)
// with one allocation; a triangle with a repeated index (a -> a) can never have a twin that is
// a different use of the edge, so it fails the uniqueness test.
bool TriMesh::closed() const {
  if (triangles.empty()) return false;
  std::vector<std::uint64_t> edges;
  edges.reserve(3 * triangles.size());
  for (const auto& t : triangles)
    for (int k = 0; k < 3; ++k) {
      const std::uint64_t a = t[k], b = t[(k + 1) % 3];
      if (a == b) return false;
      edges.push_back(a << 32 | b);
    }
  std::sort(edges.begin(), edges.end());
  if (std::adjacent_find(edges.begin(), edges.end()) != edges.end()) return false;
  for (const std::uint64_t e : edges) {
    const std::uint64_t twin = (e << 32) | (e >> 32);
    if (!std::binary_search(edges.begin(), edges.end(), twin)) return false;
  }
  return true;
}

// Divergence theorem: the sum of the tetrahedra (0, a, b, c). Taken about the first vertex
// rather than the origin so that a mesh far from the origin keeps its digits (the sum is the
// same for a closed mesh; for an open one the volume has no meaning anyway).
Real TriMesh::volume() const {
  if (vertices.empty()) return 0;
  const Vec3 o = vertices.front();
  Real six_v = 0;
  for (const auto& t : triangles)
    six_v += dot(vertices[t[0]] - o, cross(vertices[t[1]] - o, vertices[t[2]] - o));
  return six_v / 6;
}

Real TriMesh::area() const {
  Real twice = 0;
  for (const auto& t : triangles)
    twice += norm(cross(vertices[t[1]] - vertices[t[0]], vertices[t[2]] - vertices[t[0]]));
  return twice / 2;
}

}  // namespace maille
