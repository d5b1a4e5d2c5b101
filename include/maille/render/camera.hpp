// The camera of the renderer: an orbit camera around a target point, with the matrices OpenGL
// needs and the conversions between pixels and the scene (picking, framing). GL-free.
//
// Conventions: world units are metres, +y is up (gravity points to -y in the examples), angles
// are degrees. Pixel coordinates have their origin at the top-left corner of the viewport, x to
// the right and y down, as window systems report the mouse.
#pragma once

#include <array>
#include <optional>
#include <span>

#include "maille/vec3.hpp"

namespace maille::render {

// A 4x4 matrix of floats in column-major order (element (row r, column c) at m[c * 4 + r]), the
// layout glUniformMatrix4fv takes without transposition.
struct Mat4 {
  std::array<float, 16> m{};
  static Mat4 identity();
  float operator()(int row, int col) const { return m[static_cast<std::size_t>(col * 4 + row)]; }
  float& operator()(int row, int col) { return m[static_cast<std::size_t>(col * 4 + row)]; }
};
Mat4 operator*(const Mat4& a, const Mat4& b);

// An axis-aligned box, m. Empty until a point is added.
struct Bounds {
  Vec3 lo{INFINITY, INFINITY, INFINITY};
  Vec3 hi{-INFINITY, -INFINITY, -INFINITY};

  void add(const Vec3& p);
  void add(const Bounds& b);
  bool empty() const { return !(lo.x <= hi.x); }
  Vec3 centre() const;
  Real diagonal() const;  // m, 0 for a single point
};
// Box of the finite points of `points` (non-finite ones, after a blow-up, are skipped).
Bounds bounds_of(std::span<const Vec3> points);

struct Ray {
  Vec3 origin;     // m
  Vec3 direction;  // unit vector
};

struct Camera {
  Vec3 target{};        // orbit centre, m
  double distance = 5;  // eye to target, m, > 0
  double yaw = 25;      // degrees around +y; 0: the eye on +z looking toward -z
  double pitch = 15;    // degrees above the horizontal, clamped to [-89, 89]
  double fov_y = 40;    // vertical field of view, degrees, in (0, 180)

  Vec3 eye() const;
  Vec3 forward() const;  // unit vector from the eye toward the target
  Vec3 right() const;    // unit vector, screen x
  Vec3 up() const;       // unit vector, screen y
  Mat4 view() const;
  // Perspective projection for a viewport of this aspect ratio (width / height); the near and
  // far planes follow the distance so that zooming never clips the scene.
  Mat4 projection(double aspect) const;

  void orbit(double dyaw, double dpitch);  // degrees
  // Moves the target in the view plane by a mouse motion of (dx, dy) pixels in a viewport
  // `viewport_height` pixels high, so that the scene follows the cursor.
  void pan(double dx, double dy, int viewport_height);
  void zoom(double factor);  // distance *= factor (> 0); < 1 comes closer
  // Aims at the box's centre and sets the distance so that the whole box is in view with
  // `margin` (>= 1) to spare, keeping yaw and pitch. Tight for elongated boxes: every corner is
  // fitted, not just the enclosing sphere.
  void frame(const Bounds& box, double aspect, double margin = 1.08);

  // The ray from the eye through pixel (px, py) of a width x height viewport.
  Ray ray(double px, double py, int width, int height) const;
  // Pixel position of a point (x, y from the top-left) and its distance along the view axis;
  // none when the point is behind the eye.
  struct Projected {
    double x, y, depth;
  };
  std::optional<Projected> project(const Vec3& p, int width, int height) const;
};

// Keeps a camera framed on a moving scene: the box grows with every snapshot it is shown (it
// never shrinks, so a swinging pendulum is framed over its whole swing), and the camera eases
// toward the fit instead of jumping.
class AutoFrame {
 public:
  // `easing` in (0, 1]: the fraction of the way to the new fit taken per update (1: jump).
  explicit AutoFrame(double easing = 0.15) : easing_(easing) {}
  void reset() { box_ = {}; }
  // Grows the box with `points` (or with `box`: points and solids, Renderer::bounds()) and
  // moves `camera` toward the framing of the box.
  void update(Camera& camera, std::span<const Vec3> points, double aspect);
  void update(Camera& camera, const Bounds& box, double aspect);
  const Bounds& box() const { return box_; }

 private:
  double easing_;
  Bounds box_;
};

}  // namespace maille::render
