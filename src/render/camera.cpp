#include "maille/render/camera.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace maille::render {

namespace {

constexpr double kDegree = std::numbers::pi / 180;

Vec3 unit(const Vec3& v) {
  const Real n = norm(v);
  return n > 0 ? v / n : Vec3{0, 0, 0};
}

Vec3 lerp(const Vec3& a, const Vec3& b, double t) {
  return a + (b - a) * Real(t);
}

}  // namespace

Mat4 Mat4::identity() {
  Mat4 r;
  for (int i = 0; i < 4; ++i) r(i, i) = 1;
  return r;
}

Mat4 operator*(const Mat4& a, const Mat4& b) {
  Mat4 r;
  for (int row = 0; row < 4; ++row)
    for (int col = 0; col < 4; ++col) {
      float s = 0;
      for (int k = 0; k < 4; ++k) s += a(row, k) * b(k, col);
      r(row, col) = s;
    }
  return r;
}

void Bounds::add(const Vec3& p) {
  lo = {std::min(lo.x, p.x), std::min(lo.y, p.y), std::min(lo.z, p.z)};
  hi = {std::max(hi.x, p.x), std::max(hi.y, p.y), std::max(hi.z, p.z)};
}

void Bounds::add(const Bounds& b) {
  if (b.empty()) return;
  add(b.lo);
  add(b.hi);
}

Vec3 Bounds::centre() const {
  return empty() ? Vec3{} : (lo + hi) * Real(0.5);
}

Real Bounds::diagonal() const {
  return empty() ? Real(0) : norm(hi - lo);
}

Bounds bounds_of(std::span<const Vec3> points) {
  Bounds b;
  for (const Vec3& p : points)
    if (is_finite(p)) b.add(p);
  return b;
}

Vec3 Camera::eye() const {
  const double y = yaw * kDegree, p = pitch * kDegree;
  const Vec3 to_eye{Real(std::cos(p) * std::sin(y)), Real(std::sin(p)),
                    Real(std::cos(p) * std::cos(y))};
  return target + to_eye * Real(distance);
}

Vec3 Camera::forward() const {
  return unit(target - eye());
}

Vec3 Camera::right() const {
  return unit(cross(forward(), Vec3{0, 1, 0}));
}

Vec3 Camera::up() const {
  return cross(right(), forward());
}

Mat4 Camera::view() const {
  const Vec3 f = forward(), r = right(), u = up(), e = eye();
  Mat4 v = Mat4::identity();
  const Vec3 rows[3] = {r, u, -f};
  for (int i = 0; i < 3; ++i) {
    v(i, 0) = float(rows[i].x);
    v(i, 1) = float(rows[i].y);
    v(i, 2) = float(rows[i].z);
    v(i, 3) = float(-dot(rows[i], e));
  }
  return v;
}

Mat4 Camera::projection(double aspect) const {
  const double f = 1 / std::tan(fov_y * kDegree / 2);
  const double near = distance * 0.01, far = distance * 100;
  Mat4 p;
  p(0, 0) = float(f / aspect);
  p(1, 1) = float(f);
  p(2, 2) = float((far + near) / (near - far));
  p(2, 3) = float(2 * far * near / (near - far));
  p(3, 2) = -1;
  return p;
}

void Camera::orbit(double dyaw, double dpitch) {
  yaw = std::fmod(yaw + dyaw, 360.0);
  pitch = std::clamp(pitch + dpitch, -89.0, 89.0);
}

void Camera::pan(double dx, double dy, int viewport_height) {
  // One pixel spans this many metres at the target's depth.
  const double metres_per_pixel =
      2 * distance * std::tan(fov_y * kDegree / 2) / std::max(1, viewport_height);
  target += (right() * Real(-dx) + up() * Real(dy)) * Real(metres_per_pixel);
}

void Camera::zoom(double factor) {
  distance = std::clamp(distance * factor, 1e-4, 1e6);
}

void Camera::frame(const Bounds& box, double aspect, double margin) {
  if (box.empty()) return;
  target = box.centre();
  const double tan_y = std::tan(fov_y * kDegree / 2), tan_x = tan_y * aspect;
  const Vec3 r = right(), u = up(), back = -forward();
  // A corner at (x, y, z) in view axes relative to the target (z toward the eye) is in view
  // when |x| <= (d - z) tan_x and |y| <= (d - z) tan_y: each gives a least distance d.
  double d = 0;
  for (int c = 0; c < 8; ++c) {
    const Vec3 corner{(c & 1) ? box.hi.x : box.lo.x, (c & 2) ? box.hi.y : box.lo.y,
                      (c & 4) ? box.hi.z : box.lo.z};
    const Vec3 rel = corner - target;
    const double z = dot(rel, back);
    d = std::max(d, std::abs(dot(rel, r)) * margin / tan_x + z);
    d = std::max(d, std::abs(dot(rel, u)) * margin / tan_y + z);
  }
  distance = std::max({d, 0.6 * box.diagonal(), 0.1});
}

Ray Camera::ray(double px, double py, int width, int height) const {
  const double tan_y = std::tan(fov_y * kDegree / 2);
  const double tan_x = tan_y * width / std::max(1, height);
  const double nx = 2 * px / std::max(1, width) - 1, ny = 1 - 2 * py / std::max(1, height);
  const Vec3 d = forward() + right() * Real(nx * tan_x) + up() * Real(ny * tan_y);
  return {eye(), unit(d)};
}

std::optional<Camera::Projected> Camera::project(const Vec3& p, int width, int height) const {
  const Vec3 rel = p - eye();
  const double z = dot(rel, forward());
  if (!(z > distance * 0.01)) return std::nullopt;  // behind the near plane
  const double tan_y = std::tan(fov_y * kDegree / 2);
  const double tan_x = tan_y * width / std::max(1, height);
  const double nx = dot(rel, right()) / (z * tan_x), ny = dot(rel, up()) / (z * tan_y);
  return Projected{(nx + 1) / 2 * width, (1 - ny) / 2 * height, z};
}

void AutoFrame::update(Camera& camera, std::span<const Vec3> points, double aspect) {
  update(camera, bounds_of(points), aspect);
}

void AutoFrame::update(Camera& camera, const Bounds& box, double aspect) {
  const bool first = box_.empty();
  box_.add(box);
  if (box_.empty()) return;
  Camera fit = camera;
  fit.frame(box_, aspect);
  const double t = first ? 1.0 : easing_;
  camera.target = lerp(camera.target, fit.target, t);
  camera.distance += (fit.distance - camera.distance) * t;
}

}  // namespace maille::render
