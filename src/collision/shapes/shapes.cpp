// Canonical distance functions (see include/maille/shapes.hpp). Solids of revolution about y
// (cylinder, cone, capsule, torus) are solved in their (r, y) half-plane and turned back to 3-D
// along the radial direction (+x on the axis).
#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

#include "maille/shapes.hpp"

namespace maille::shapes {

namespace {

// The radial unit vector of p about the y axis, +x on the axis; r its distance to the axis.
Vec3 radial(const Vec3& p, Real& r) {
  r = std::sqrt(p.x * p.x + p.z * p.z);
  return r > 0 ? Vec3{p.x / r, 0, p.z / r} : Vec3{1, 0, 0};
}

struct Point2 {
  Real r, y;
};

// Closest point to q on segment ab (2-D).
Point2 closest_on_segment(Point2 q, Point2 a, Point2 b) {
  const Real dr = b.r - a.r, dy = b.y - a.y;
  const Real len2 = dr * dr + dy * dy;
  Real t = len2 > 0 ? ((q.r - a.r) * dr + (q.y - a.y) * dy) / len2 : 0;
  t = std::clamp<Real>(t, 0, 1);
  return {a.r + t * dr, a.y + t * dy};
}

// A convex polygon of the (r, y) half-plane given by its boundary edges (those not on the
// axis), with an inside test: the distance to the closest edge, signed, and the normal there.
// Ties go to the first edge in the list (callers list caps first: +y before the side).
template <int N>
Distance revolve(const Vec3& p, const Point2 (&edges)[N][2], bool inside) {
  Real r;
  const Vec3 out = radial(p, r);
  const Point2 q{r, p.y};
  Real best = std::numeric_limits<Real>::max();
  Point2 c{0, 0};
  int which = 0;
  for (int e = 0; e < N; ++e) {
    const Point2 k = closest_on_segment(q, edges[e][0], edges[e][1]);
    const Real d2 = (q.r - k.r) * (q.r - k.r) + (q.y - k.y) * (q.y - k.y);
    if (d2 < best) best = d2, c = k, which = e;
  }
  const Real d = std::sqrt(best);
  Real nr, ny;
  if (d > 0) {
    nr = (q.r - c.r) / d, ny = (q.y - c.y) / d;
    if (inside) nr = -nr, ny = -ny;
  } else {  // on the surface: the edge's outward normal (edges run counter-clockwise)
    const Point2 a = edges[which][0], b = edges[which][1];
    const Real er = b.r - a.r, ey = b.y - a.y, len = std::sqrt(er * er + ey * ey);
    nr = ey / len, ny = -er / len;
  }
  return {inside ? -d : d, out * nr + Vec3{0, ny, 0}};
}

}  // namespace

// Ties: the centre gets +y.
Distance sphere(const Vec3& p) {
  const Real n = norm(p);
  return {n - 1, n > 0 ? p / n : Vec3{0, 1, 0}};
}

// Outside: the Euclidean distance to the box (the max norm's level set 1 is the surface);
// inside: the distance to the nearest face. Ties between faces: y, then x, then z.
Distance cube(const Vec3& p) {
  const Vec3 q{std::abs(p.x) - 1, std::abs(p.y) - 1, std::abs(p.z) - 1};
  const Vec3 s{p.x < 0 ? Real(-1) : Real(1), p.y < 0 ? Real(-1) : Real(1),
               p.z < 0 ? Real(-1) : Real(1)};
  const Vec3 o{std::max<Real>(q.x, 0), std::max<Real>(q.y, 0), std::max<Real>(q.z, 0)};
  const Real outside = norm(o);
  if (outside > 0) return {outside, Vec3{s.x * o.x, s.y * o.y, s.z * o.z} / outside};
  // Inside or on the surface: the largest of q (closest face), y first on ties.
  if (q.y >= q.x && q.y >= q.z) return {q.y, {0, s.y, 0}};
  if (q.x >= q.z) return {q.x, {s.x, 0, 0}};
  return {q.z, {0, 0, s.z}};
}

Distance cylinder(const Vec3& p) {
  Real r;
  radial(p, r);
  const bool inside = r < 1 && std::abs(p.y) < 1;
  static const Point2 edges[3][2] = {{{1, 1}, {0, 1}}, {{0, -1}, {1, -1}}, {{1, -1}, {1, 1}}};
  return revolve(p, edges, inside);
}

Distance cone(const Vec3& p, Real top) {
  Real r;
  radial(p, r);
  const Real radius_at_y = 1 + (top - 1) * (p.y + 1) / 2;
  const bool inside = std::abs(p.y) < 1 && r < radius_at_y;
  const Point2 edges[3][2] = {{{top, 1}, {0, 1}}, {{0, -1}, {1, -1}}, {{1, -1}, {top, 1}}};
  if (top <= 0) {  // a pointed cone: no top cap (the first edge degenerates to its apex)
    const Point2 pointed[2][2] = {{{0, -1}, {1, -1}}, {{1, -1}, {0, 1}}};
    return revolve(p, pointed, inside);
  }
  return revolve(p, edges, inside);
}

// The tube about the unit circle: ties (on the circle itself) get +y; on the axis, +x.
Distance torus(const Vec3& p, Real tube) {
  Real r;
  const Vec3 out = radial(p, r);
  const Real qr = r - 1, qy = p.y;
  const Real len = std::sqrt(qr * qr + qy * qy);
  if (len == 0) return {-tube, {0, 1, 0}};
  return {len - tube, out * (qr / len) + Vec3{0, qy / len, 0}};
}

// The segment's closest point; on the segment itself (the axis inside), +x.
Distance capsule(const Vec3& p) {
  const Vec3 c{0, std::clamp<Real>(p.y, -1, 1), 0};
  const Vec3 d = p - c;
  const Real n = norm(d);
  return {n - 1, n > 0 ? d / n : Vec3{1, 0, 0}};
}

Distance half_space(const Vec3& p) {
  return {p.y, {0, 1, 0}};
}

// ---------------------------------------------------------------------------------------------

Affine Affine::from(const Vec3& position, const Vec3& rotation_degrees, const Vec3& scale) {
  constexpr double deg = std::numbers::pi / 180;
  auto rot = [](int axis, double angle) {
    const Real c = Real(std::cos(angle)), s = Real(std::sin(angle));
    Mat3 m = Mat3::identity();
    const int i = (axis + 1) % 3, j = (axis + 2) % 3;
    m.m[i][i] = c, m.m[i][j] = -s, m.m[j][i] = s, m.m[j][j] = c;
    return m;
  };
  auto mul = [](const Mat3& a, const Mat3& b) {
    Mat3 r{};
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j)
        for (int k = 0; k < 3; ++k) r.m[i][j] += a.m[i][k] * b.m[k][j];
    return r;
  };
  const Mat3 R = mul(rot(2, rotation_degrees.z * deg),
                     mul(rot(1, rotation_degrees.y * deg), rot(0, rotation_degrees.x * deg)));
  Mat3 S = Mat3::identity(), Si = Mat3::identity();
  S.m[0][0] = scale.x, S.m[1][1] = scale.y, S.m[2][2] = scale.z;
  Si.m[0][0] = 1 / scale.x, Si.m[1][1] = 1 / scale.y, Si.m[2][2] = 1 / scale.z;
  Mat3 Rt{};
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) Rt.m[i][j] = R.m[j][i];
  Affine a;
  a.direct = mul(R, S);
  a.inverse = mul(Si, Rt);
  a.translation = position;
  return a;
}

Vec3 Affine::normal_to_world(const Vec3& n) const {
  Vec3 w{};  // M_i^T n
  const auto& m = inverse.m;
  w.x = m[0][0] * n.x + m[1][0] * n.y + m[2][0] * n.z;
  w.y = m[0][1] * n.x + m[1][1] * n.y + m[2][1] * n.z;
  w.z = m[0][2] * n.x + m[1][2] * n.y + m[2][2] * n.z;
  const Real l = norm(w);
  return l > 0 ? w / l : Vec3{0, 1, 0};
}

Affine Affine::moved(const Mat3& R, const Vec3& center, const Vec3& offset) const {
  Affine a;
  a.direct = R * direct;
  a.inverse = inverse * transpose(R);  // R is orthogonal: R^-1 = R^T
  a.translation = R * (translation - center) + center + offset;
  return a;
}

Mat3 rotation(const Vec3& k, double angle) {
  const Real c = Real(std::cos(angle)), s = Real(std::sin(angle)), t = 1 - c;
  Mat3 r;
  r.m[0][0] = c + t * k.x * k.x, r.m[0][1] = t * k.x * k.y - s * k.z;
  r.m[0][2] = t * k.x * k.z + s * k.y;
  r.m[1][0] = t * k.y * k.x + s * k.z, r.m[1][1] = c + t * k.y * k.y;
  r.m[1][2] = t * k.y * k.z - s * k.x;
  r.m[2][0] = t * k.z * k.x - s * k.y, r.m[2][1] = t * k.z * k.y + s * k.x;
  r.m[2][2] = c + t * k.z * k.z;
  return r;
}

Distance canonical(ShapeKind s, const Vec3& p, Real top, Real tube) {
  switch (s) {
    case ShapeKind::sphere:
      return sphere(p);
    case ShapeKind::cube:
      return cube(p);
    case ShapeKind::cylinder:
      return cylinder(p);
    case ShapeKind::cone:
      return cone(p, top);
    case ShapeKind::torus:
      return torus(p, tube);
    case ShapeKind::capsule:
      return capsule(p);
    case ShapeKind::plane:
      return half_space(p);
  }
  return {};
}

}  // namespace maille::shapes
