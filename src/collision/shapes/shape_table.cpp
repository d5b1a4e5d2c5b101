// The shape table: one row per canonical shape, in kShape* order. A shape is its distance
// function and its case in canonical_distance (include/maille/detail/obstacle_laws.glsl: the CPU
// and the GPU's kernels share them) and its row here: its name in scene files, its docs, its
// parameter if it has one (the scene key [[obstacle]] and [[geometric_point]] take for it, its
// default and range: include/maille/shape_keys.hpp declares the keys), its mesh (the facet and
// conditional methods, drawing), the radius of a sphere holding it (the geometric obstacle's
// cull) and its thinnest extent (the implicit solvers' contact thickness). Nothing else names a
// shape: docs/scene-format.md's rows are generated (`maille info --keys --update-docs`).
#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

#include "../mesh/tessellation.hpp"
#include "maille/shapes.hpp"
#include "maille/shared_laws.hpp"

namespace maille {

namespace {

using namespace tessellation;

constexpr Real kUnbounded = std::numeric_limits<Real>::infinity();

constexpr std::array kShapes{
    ShapeRow{.name = "sphere",
             .doc = "radius 1",
             .number = law::kShapeSphere,
             .mesh =
                 [](int n, Real) {
                   Profile p({0, -1});
                   p.arc_to({0, 0}, 1, -kPi / 2, kPi / 2, {0, 1}, steps(kPi, n));
                   return revolve(p.points(), n, false);
                 },
             .reach = [](Real) { return Real(1); },
             .thinnest = [](Real) { return Real(2); }},
    ShapeRow{.name = "cube",
             .doc = "[-1,1]³",
             .number = law::kShapeCube,
             .mesh = [](int n, Real) { return box_grid(std::max(1, n / 4)); },
             .reach = [](Real) { return std::sqrt(Real(3)); },
             .thinnest = [](Real) { return Real(2); }},
    ShapeRow{.name = "cylinder",
             .doc = "along y, radius 1, y from -1 to 1, capped",
             .number = law::kShapeCylinder,
             .mesh =
                 [](int n, Real) {
                   Profile p({0, -1});
                   p.line_to({1, -1}, steps(1, n));
                   p.line_to({1, 1}, steps(2, n));
                   p.line_to({0, 1}, steps(1, n));
                   return revolve(p.points(), n, false);
                 },
             .reach = [](Real) { return std::sqrt(Real(2)); },
             .thinnest = [](Real) { return Real(2); }},
    // A frustum; top == 0 ends at the apex (0, 1), which is a pole: still closed. Its thinnest
    // extent: the top's diameter, taken as 0.2 at least.
    ShapeRow{
        .name = "cone",
        .doc = "a frustum along y, radius 1 at y = -1 and `top` at y = 1",
        .number = law::kShapeCone,
        .parameter = ShapeParameter{.key = "top",
                                    .fallback = Real(0.5),
                                    .bound = Bound::non_negative,
                                    .lo = 0,
                                    .hi = 1,
                                    .range_doc = "[0, 1]",
                                    .doc = "cone only: top radius / bottom radius (0: pointed)",
                                    .refusal = "only a cone has a top radius"},
        .mesh =
            [](int n, Real top) {
              const double t = double(top);
              Profile p({0, -1});
              p.line_to({1, -1}, steps(1, n));
              p.line_to({t, 1}, steps(std::hypot(2.0, 1 - t), n));
              if (t > 0) p.line_to({0, 1}, steps(t, n));
              return revolve(p.points(), n, false);
            },
        .reach = [](Real) { return std::sqrt(Real(2)); },
        .thinnest = [](Real top) { return 2 * std::max(top, Real(0.1)); }},
    // The mesh: the tube's circle about (1, 0), counter-clockwise from its outer point, as a
    // closed loop; about as many segments around the tube as its circumference asks for, at
    // least 3.
    ShapeRow{.name = "torus",
             .doc = "about y, major radius 1, tube radius `tube`",
             .number = law::kShapeTorus,
             .parameter = ShapeParameter{.key = "tube",
                                         .fallback = Real(0.3),
                                         .bound = Bound::positive,
                                         .lo = 0,
                                         .hi = 1,
                                         .range_doc = "(0, 1]",
                                         .doc = "torus only: tube radius / major radius",
                                         .refusal = "only a torus has a tube"},
             .mesh =
                 [](int n, Real tube) {
                   const double t = double(tube);
                   const int m = std::max(3, steps(2 * kPi * t, n));
                   std::vector<P2> loop;
                   for (int i = 0; i < m; ++i) {
                     const double a = 2 * kPi * i / m;
                     // tube = 1 touches the axis (a horn torus): that point is a pole, exactly r =
                     // 0.
                     const double r = 1 + t * std::cos(a);
                     loop.push_back({r < 1e-12 ? 0.0 : r, t * std::sin(a)});
                   }
                   return revolve(loop, n, true);
                 },
             .reach = [](Real tube) { return 1 + tube; },
             .thinnest = [](Real tube) { return 2 * tube; }},
    // A cylinder of radius 1 from y = -1 to 1 between two hemispheres (centres y = -1 and 1).
    ShapeRow{.name = "capsule",
             .doc = "the segment y in [-1, 1] grown by 1",
             .number = law::kShapeCapsule,
             .mesh =
                 [](int n, Real) {
                   Profile p({0, -2});
                   p.arc_to({0, -1}, 1, -kPi / 2, 0, {1, -1}, steps(kPi / 2, n));
                   p.line_to({1, 1}, steps(2, n));
                   p.arc_to({0, 1}, 1, 0, kPi / 2, {0, 2}, steps(kPi / 2, n));
                   return revolve(p.points(), n, false);
                 },
             .reach = [](Real) { return Real(2); },
             .thinnest = [](Real) { return Real(2); }},
    ShapeRow{.name = "plane",
             .doc = "the half-space y <= 0 for `geometric`, the square [-1,1]×{0}×[-1,1] (normal "
                    "+y) otherwise",
             .number = law::kShapePlane,
             .mesh = [](int n, Real) { return square_grid(n); },
             .min_resolution = 1,
             .reach = [](Real) { return kUnbounded; },
             .thinnest = [](Real) { return kUnbounded; }},
};

// Each row's number is its index (the GPU and the law dispatch on it); names and parameter keys
// are unique.
constexpr bool numbered_in_order() {
  for (std::size_t i = 0; i < kShapes.size(); ++i) {
    if (kShapes[i].number != int(i)) return false;
    for (std::size_t j = 0; j < i; ++j) {
      if (kShapes[j].name == kShapes[i].name) return false;
      if (kShapes[j].parameter && kShapes[i].parameter &&
          kShapes[j].parameter->key == kShapes[i].parameter->key)
        return false;
    }
  }
  return true;
}
static_assert(numbered_in_order(), "a shape's kShape* number (obstacle_laws.glsl) is its row");
static_assert(std::count_if(kShapes.begin(), kShapes.end(),
                            [](const ShapeRow& r) { return r.parameter.has_value(); }) <=
                  long(kMaxShapeParameters),
              "more shapes with a parameter than shape_keys.hpp has slots");

}  // namespace

std::span<const ShapeRow> shape_table() {
  return kShapes;
}

}  // namespace maille
