// Mat3: the 3x3 blocks of link Jacobians (implicit integration).
#pragma once

#include "maille/vec3.hpp"

namespace maille {

struct Mat3 {
  Real m[3][3] = {{0, 0, 0}, {0, 0, 0}, {0, 0, 0}};  // row-major

  static constexpr Mat3 identity() {
    Mat3 r;
    r.m[0][0] = r.m[1][1] = r.m[2][2] = 1;
    return r;
  }
  // a b^T
  static constexpr Mat3 outer(const Vec3& a, const Vec3& b) {
    Mat3 r;
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) r.m[i][j] = a[i] * b[j];
    return r;
  }
  constexpr Mat3& operator+=(const Mat3& o) {
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) m[i][j] += o.m[i][j];
    return *this;
  }
  constexpr Mat3& operator*=(Real s) {
    for (auto& row : m)
      for (Real& e : row) e *= s;
    return *this;
  }
};

constexpr Mat3 operator+(Mat3 a, const Mat3& b) {
  return a += b;
}
constexpr Mat3 operator-(Mat3 a, const Mat3& b) {
  return a += (Mat3(b) *= Real(-1));
}
constexpr Mat3 operator*(Mat3 a, Real s) {
  return a *= s;
}
constexpr Mat3 operator*(Real s, Mat3 a) {
  return a *= s;
}
constexpr Vec3 operator*(const Mat3& a, const Vec3& v) {
  return {a.m[0][0] * v.x + a.m[0][1] * v.y + a.m[0][2] * v.z,
          a.m[1][0] * v.x + a.m[1][1] * v.y + a.m[1][2] * v.z,
          a.m[2][0] * v.x + a.m[2][1] * v.y + a.m[2][2] * v.z};
}

constexpr Mat3 operator*(const Mat3& a, const Mat3& b) {
  Mat3 r;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      r.m[i][j] = a.m[i][0] * b.m[0][j] + a.m[i][1] * b.m[1][j] + a.m[i][2] * b.m[2][j];
  return r;
}
constexpr Mat3 transpose(const Mat3& a) {
  Mat3 r;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) r.m[i][j] = a.m[j][i];
  return r;
}
// a^T v without forming the transpose (normals through an inverse transpose).
constexpr Vec3 transpose_times(const Mat3& a, const Vec3& v) {
  return {a.m[0][0] * v.x + a.m[1][0] * v.y + a.m[2][0] * v.z,
          a.m[0][1] * v.x + a.m[1][1] * v.y + a.m[2][1] * v.z,
          a.m[0][2] * v.x + a.m[1][2] * v.y + a.m[2][2] * v.z};
}

// Derivatives of a link's force on its first point a, with respect to the state of its second
// point b (the force depends on x_b - x_a and v_b - v_a only, so the derivatives with respect
// to a are the opposites, and b's force, -f_a, has the opposite derivatives again).
struct LinkJacobian {
  Mat3 dx;  // d f_a / d x_b, N/m
  Mat3 dv;  // d f_a / d v_b, N.s/m
};

// A link's terms for vertex block descent at one end: the force on a, and the block
// J_x + J_v / h (definite mode), which is the same at both ends.
struct LinkBlock {
  Vec3 force;      // N
  Mat3 stiffness;  // N/m
};

// A central link's terms for vertex block descent, from its axis d = x_b - x_a alone (kinds
// that offer `axial`, e.g. SpringDamper): the force on a is force d, the block is
// iso I + axial d d^T. LinkPool evaluates such kinds in lanes (link_pool.hpp).
struct AxialTerms {
  Real force;  // N/m
  Real iso;    // N/m
  Real axial;  // N/m^3
};

// The block iso I + axial d d^T of AxialTerms.
inline Mat3 axial_block(const Vec3& d, const AxialTerms& a) {
  Mat3 out = Mat3::outer(d, d) * a.axial;
  for (int i = 0; i < 3; ++i) out.m[i][i] += a.iso;
  return out;
}

// What the implicit solver needs from a Jacobian: the exact derivative (tests, Newton), or a
// symmetric negative semi-definite approximation that keeps M - h df/dv - h^2 df/dx symmetric
// positive definite for conjugate gradients: compressed springs drop their negative
// transverse term (Choi & Ko 2002) and dampers drop the non-symmetric position derivative
// of their direction (Baraff & Witkin 1998).
enum class JacobianMode { exact, definite };

}  // namespace maille
