// Spring (linear, Hooke): f_a = k (|d| - L0) d/|d|,  d = x_b - x_a.  Energy 1/2 k (|d| - L0)^2.
#pragma once

#include <algorithm>
#include <array>

#include "maille/link_kind.hpp"
#include "maille/mat3.hpp"
#include "maille/shared_laws.hpp"

namespace maille {

// Unit direction and length of d = xb - xa; a zero-length link has no direction (n = 0).
struct Separation {
  Real length = 0;
  Vec3 n{};
};
// Lengths below kTinyLength are treated as zero (see law::inverse_length, the shared laws).
inline constexpr Real kTinyLength = Real(1e-30);  // m

inline Real inverse_length(const Vec3& d) {
  return law::inverse_length(d);
}

inline Separation separation(const Vec3& xa, const Vec3& xb) {
  const Vec3 d = xb - xa;
  const Real len = norm(d);
  return {len, d * (Real(1) / (len + kTinyLength))};
}

// d/dd of k (|d| - L0) d/|d|:  k [ n n^T + (1 - L0/|d|) (I - n n^T) ] (the shared law,
// link_laws.glsl). In definite mode the transverse factor is clamped at 0 (a compressed spring
// would otherwise contribute a negative stiffness and the implicit system could lose
// definiteness).
inline Mat3 spring_jacobian(const Vec3& d, Real k, Real rest, JacobianMode mode) {
  return law::spring_dx(d, k, rest, mode == JacobianMode::definite);
}

// Derivatives of the axial damper z ((v_b - v_a).n) n. d/d(dv) = z n n^T (the shared law,
// link_laws.glsl); d/dd, from the turning of n, = z/|d| [ n (P dv)^T + (dv.n) P ] with
// P = I - n n^T: not symmetric, dropped in definite mode (as Baraff & Witkin do).
inline LinkJacobian damper_jacobian(const Vec3& d, const Vec3& dv, Real z, JacobianMode mode) {
  LinkJacobian j;
  j.dv = law::axial_dv(d, z);
  if (mode == JacobianMode::exact) {
    const Real inv = inverse_length(d);
    const Vec3 n = d * inv;
    const Mat3 P = Mat3::identity() - Mat3::outer(n, n);
    j.dx = (Mat3::outer(n, P * dv) + P * dot(dv, n)) * (z * inv);
  }
  return j;
}

// The spring's two scene fields, shared by every kind with a spring term (spring,
// spring_damper): one declaration of their unit, bound, default and doc.
template <class Params>
constexpr ParamField<Params> stiffness_field() {
  return {"stiffness", "N/m", &Params::stiffness, Bound::non_negative, {}, false, "k"};
}
template <class Params>
constexpr ParamField<Params> rest_length_field() {
  return {"rest_length",
          "m",
          &Params::rest_length,
          Bound::non_negative,
          {},
          true,
          "L0; default: the distance between the points in the scene"};
}

struct Spring {
  static constexpr std::string_view keyword = "spring";
  static constexpr std::string_view shared_law = "spring_law";  // link_laws.glsl
  struct Params {
    Real stiffness = 0;    // k, N/m
    Real rest_length = 0;  // L0, m
  };
  static constexpr std::array<ParamField<Params>, 2> fields{
      {stiffness_field<Params>(), rest_length_field<Params>()}};

  static Vec3 force(const Vec3& xa, const Vec3& xb, const Vec3& va, const Vec3& vb,
                    const Params& p) {
    return law::spring_law(xa, xb, va, vb, p.stiffness, p.rest_length);
  }
  static Real energy(const Vec3& xa, const Vec3& xb, const Params& p) {
    const Real e = norm(xb - xa) - p.rest_length;
    return Real(0.5) * p.stiffness * e * e;
  }
  static LinkJacobian jacobian(const Vec3& xa, const Vec3& xb, const Vec3&, const Vec3&,
                               const Params& p, JacobianMode mode) {
    return {spring_jacobian(xb - xa, p.stiffness, p.rest_length, mode), Mat3{}};
  }
  static Real stiffness(const Params& p) { return p.stiffness; }
  static Real damping(const Params&) { return 0; }
};

}  // namespace maille
