#include "maille/intersections.hpp"

#include <algorithm>
#include <cmath>

namespace maille {
namespace {

// The side of the plane (a, b, c) that d is on: the sign of six times the signed volume of the
// tetrahedron (a, b, c, d), 0 within kFlat of the volume's scale |b - a| |c - a| |d - a|. Below
// that the sign is rounding noise (a flat cloth's neighbours are coplanar up to 1e-16 of their
// size, and random signs there made the line through an edge seem to pierce a neighbour): such
// a configuration is touching, not crossing.
constexpr Real kFlat = 1e-12;
int side(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d) {
  const Vec3 ab = b - a, ac = c - a, ad = d - a;
  const Real v = dot(cross(ab, ac), ad);
  const Real scale = std::sqrt(norm2(ab) * norm2(ac) * norm2(ad));
  if (!(std::abs(v) > kFlat * scale)) return 0;
  return v > 0 ? 1 : -1;
}

// Segment pq crosses the interior of triangle abc: p and q strictly on both sides of its plane,
// and the line pq strictly inside its three edges (the three volumes of the same sign).
bool segment_crosses(const Vec3& p, const Vec3& q, const Vec3& a, const Vec3& b, const Vec3& c) {
  const int sp = side(a, b, c, p), sq = side(a, b, c, q);
  if (sp == 0 || sq == 0 || sp == sq) return false;
  const int s1 = side(p, q, a, b), s2 = side(p, q, b, c), s3 = side(p, q, c, a);
  return s1 != 0 && s1 == s2 && s2 == s3;
}

}  // namespace

bool triangles_cross(const Vec3& a0, const Vec3& a1, const Vec3& a2, const Vec3& b0, const Vec3& b1,
                     const Vec3& b2) {
  return segment_crosses(a0, a1, b0, b1, b2) || segment_crosses(a1, a2, b0, b1, b2) ||
         segment_crosses(a2, a0, b0, b1, b2) || segment_crosses(b0, b1, a0, a1, a2) ||
         segment_crosses(b1, b2, a0, a1, a2) || segment_crosses(b2, b0, a0, a1, a2);
}

std::size_t IntersectionCount::count(std::span<const Vec3> x, std::span<const Triangle> tris) {
  const std::size_t n = tris.size();
  boxes_.resize(n);
  order_.resize(n);
  pairs_.clear();
  for (std::size_t t = 0; t < n; ++t) {
    const Vec3 &a = x[tris[t][0]], &b = x[tris[t][1]], &c = x[tris[t][2]];
    boxes_[t] = {{std::min({a.x, b.x, c.x}), std::min({a.y, b.y, c.y}), std::min({a.z, b.z, c.z})},
                 {std::max({a.x, b.x, c.x}), std::max({a.y, b.y, c.y}), std::max({a.z, b.z, c.z})}};
    order_[t] = std::uint32_t(t);
  }
  std::sort(order_.begin(), order_.end(), [&](std::uint32_t s, std::uint32_t t) {
    return boxes_[s].lo.x < boxes_[t].lo.x || (boxes_[s].lo.x == boxes_[t].lo.x && s < t);
  });
  std::size_t found = 0;
  active_.clear();
  for (const std::uint32_t t : order_) {
    const Box& q = boxes_[t];
    // Boxes that end before this one starts along x leave the sweep.
    active_.erase(std::remove_if(active_.begin(), active_.end(),
                                 [&](std::uint32_t s) { return boxes_[s].hi.x < q.lo.x; }),
                  active_.end());
    for (const std::uint32_t s : active_) {
      const Box& p = boxes_[s];
      if (p.hi.y < q.lo.y || q.hi.y < p.lo.y || p.hi.z < q.lo.z || q.hi.z < p.lo.z) continue;
      const Triangle &u = tris[s], &w = tris[t];
      bool shared = false;
      for (const std::uint32_t i : u)
        for (const std::uint32_t j : w) shared = shared || i == j;
      if (shared) continue;
      if (!triangles_cross(x[u[0]], x[u[1]], x[u[2]], x[w[0]], x[w[1]], x[w[2]])) continue;
      ++found;
      if (pairs_.size() < keep_) pairs_.push_back({std::min(s, t), std::max(s, t)});
    }
    active_.push_back(t);
  }
  return found;
}

}  // namespace maille
