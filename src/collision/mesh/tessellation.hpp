// The pieces the shape table's meshes are built from (src/collision/shapes/shape_table.cpp;
// tessellate.cpp has them, with the sweep's rationale).
//
// The solids of revolution are one algorithm: a profile polyline in the (r, y) half-plane, run
// counter-clockwise (r to the right, y up), swept about the y axis in `n` equal steps; a profile
// point with r == 0 is a single vertex on the axis. Segments along the profile are about as long
// as those around (2 pi / n at radius 1): steps(length, n) of them for a length.
#pragma once

#include <algorithm>
#include <cmath>
#include <numbers>
#include <vector>

#include "maille/mesh.hpp"

namespace maille::tessellation {

inline constexpr double kPi = std::numbers::pi;

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
inline int steps(double length, int n) {
  return std::max(1, static_cast<int>(std::ceil(length * n / (2 * kPi) - 1e-9)));
}

// The sweep of `profile` about y in n steps. `loop`: the profile closes on itself (a torus).
TriMesh revolve(const std::vector<P2>& profile, int n, bool loop);
// [-1, 1]^3 as six faces of k x k squares, welded.
TriMesh box_grid(int k);
// The square [-1, 1] x {0} x [-1, 1] as k x k squares, facing +y.
TriMesh square_grid(int k);

}  // namespace maille::tessellation
