// Canonical distance functions (see include/maille/shapes.hpp), from the shared law file, and
// the placements.
#include <cmath>
#include <numbers>

#include "maille/shapes.hpp"
#include "maille/shared_laws.hpp"

namespace maille::shapes {

// The distance functions are the shared law's (include/maille/detail/obstacle_laws.glsl), which
// the GPU's obstacle kernels paste: its shape numbers are ShapeKind's.
static_assert(law::kShapeSphere == int(ShapeKind::sphere) &&
              law::kShapeCube == int(ShapeKind::cube) &&
              law::kShapeCylinder == int(ShapeKind::cylinder) &&
              law::kShapeCone == int(ShapeKind::cone) &&
              law::kShapeTorus == int(ShapeKind::torus) &&
              law::kShapeCapsule == int(ShapeKind::capsule) &&
              law::kShapePlane == int(ShapeKind::plane));

namespace {
// The shared law's distance (obstacle_laws.glsl: shape parameters, then the normal out).
template <class Law, class... Params>
Distance measured(Law law, const Vec3& p, Params... params) {
  Distance d;
  d.signed_distance = law(p, params..., d.normal);
  return d;
}
}  // namespace

Distance sphere(const Vec3& p) {
  return measured(law::sphere_distance, p);
}
Distance cube(const Vec3& p) {
  return measured(law::cube_distance, p);
}
Distance cylinder(const Vec3& p) {
  return measured(law::cylinder_distance, p);
}
Distance cone(const Vec3& p, Real top) {
  return measured(law::cone_distance, p, top);
}
Distance torus(const Vec3& p, Real tube) {
  return measured(law::torus_distance, p, tube);
}
Distance capsule(const Vec3& p) {
  return measured(law::capsule_distance, p);
}
Distance half_space(const Vec3& p) {
  return measured(law::half_space_distance, p);
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
  return law::normal_to_world(inverse, n);
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
  Distance d;
  d.signed_distance = law::canonical_distance(int(s), p, top, tube, d.normal);
  return d;
}

}  // namespace maille::shapes
