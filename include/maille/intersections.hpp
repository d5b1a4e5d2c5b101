// Pairs of triangles that intersect: the witness of a cloth passing through itself (stats.csv's
// `intersecting_pairs`, `[self_collision] check`, `maille validate`). A pair counts when an edge
// of one triangle crosses the interior of the other: its ends strictly on both sides of the
// other's plane, and the crossing strictly inside the triangle. The test is the sign of signed
// volumes (orient3d): two triangles that only touch (a shared edge or corner, a vertex on a
// face, coplanar overlap) do not count; pairs sharing a corner are left out. Signs are taken in
// double precision, a volume within 1e-12 of its scale (|b - a| |c - a| |d - a|) counting as
// flat: rounding noise is touching, and a crossing shallower than that (1e-13 m for 10 cm
// triangles) is not seen.
#pragma once

#include <array>
#include <cstdint>
#include <span>
#include <vector>

#include "maille/vec3.hpp"

namespace maille {

using Triangle = std::array<std::uint32_t, 3>;

// Whether triangles (a0, a1, a2) and (b0, b1, b2) cross (as above; shared corners not checked).
bool triangles_cross(const Vec3& a0, const Vec3& a1, const Vec3& a2, const Vec3& b0, const Vec3& b1,
                     const Vec3& b2);

// Counts the crossing pairs among `triangles` (corners index x): boxes swept along x, then the
// test above on overlapping boxes. Keeps its working arrays between calls.
class IntersectionCount {
 public:
  std::size_t count(std::span<const Vec3> x, std::span<const Triangle> triangles);
  // The pairs found by the last count (indices into `triangles`, the lower first), at most
  // `keep` of them (0: none kept).
  std::span<const std::array<std::uint32_t, 2>> pairs() const { return pairs_; }
  void keep_pairs(std::size_t keep) { keep_ = keep; }

 private:
  struct Box {
    Vec3 lo, hi;
  };
  std::vector<Box> boxes_;
  std::vector<std::uint32_t> order_, active_;
  std::vector<std::array<std::uint32_t, 2>> pairs_;
  std::size_t keep_ = 0;
};

}  // namespace maille
