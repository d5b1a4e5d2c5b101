// Spring-damper: a spring and an axial dashpot in parallel, sharing one direction computation.
//   f_a = [k (|d| - L0) + z (v_b - v_a).n] n
#pragma once

#include <array>
#include <cmath>

#include "maille/links/spring.hpp"

namespace maille {

// The shared law of spring-dampers and conditional links: pure, value in, value out.
inline Vec3 spring_damper_force(const Separation& s, const Vec3& dv, Real k, Real rest, Real z) {
  return s.n * (k * (s.length - rest) + z * dot(dv, s.n));
}

struct SpringDamper {
  static constexpr std::string_view keyword = "spring_damper";
  static constexpr std::string_view shared_law = "spring_damper_law";  // link_laws.glsl
  static constexpr bool grid_stencil = true;  // grid links run structured (structured_grid.hpp)
  struct Params {
    Real stiffness = 0;    // k, N/m
    Real rest_length = 0;  // L0, m
    Real damping = 0;      // z, N.s/m
  };
  static constexpr std::array<ParamField<Params>, 3> fields{
      {stiffness_field<Params>(),
       rest_length_field<Params>(),
       {"damping", "N.s/m", &Params::damping, Bound::non_negative, Real(0), false, "z"}}};

  // Written on d itself (one sqrt, one division, no normalised n): with inv = 1/|d|,
  //   f_a = [k (1 - L0 inv) + z (dv.d) inv^2] d
  static Vec3 force(const Vec3& xa, const Vec3& xb, const Vec3& va, const Vec3& vb,
                    const Params& p) {
    return law::spring_damper_law(xa, xb, va, vb, p.stiffness, p.rest_length, p.damping);
  }
  static LinkJacobian jacobian(const Vec3& xa, const Vec3& xb, const Vec3& va, const Vec3& vb,
                               const Params& p, JacobianMode mode) {
    LinkJacobian j = damper_jacobian(xb - xa, vb - va, p.damping, mode);
    j.dx += spring_jacobian(xb - xa, p.stiffness, p.rest_length, mode);
    return j;
  }
  // Vertex block descent's per-link terms in one pass (optional for a kind: without it the
  // pool calls force and jacobian): the force, and J_x + J_v / h in definite mode,
  //   k t I + (k (1 - t) + z / h) n n^T,  t = max(0, 1 - L0 / |d|),
  // with one square root instead of three (the same values up to rounding). Written from the
  // axis alone (|d|^2 and dv.d), so that the pool runs it in lanes over many links at once:
  // n n^T = d d^T / |d|^2.
  static AxialTerms axial(Real d2, Real dvd, const Params& p, Real inv_h) {
    const Real inv = Real(1) / (std::sqrt(d2) + Real(1e-30));  // law::inverse_length
    const Real stretch = 1 - p.rest_length * inv;
    const Real t = stretch > 0 ? stretch : Real(0);
    return {p.stiffness * stretch + p.damping * dvd * inv * inv, p.stiffness * t,
            (p.stiffness * (1 - t) + p.damping * inv_h) * (inv * inv)};
  }
  static LinkBlock block(const Vec3& xa, const Vec3& xb, const Vec3& va, const Vec3& vb,
                         const Params& p, Real inv_h) {
    const Vec3 d = xb - xa;
    const AxialTerms a = axial(dot(d, d), dot(vb - va, d), p, inv_h);
    return {d * a.force, axial_block(d, a)};
  }
  static Real energy(const Vec3& xa, const Vec3& xb, const Params& p) {
    const Real e = norm(xb - xa) - p.rest_length;
    return Real(0.5) * p.stiffness * e * e;
  }
  static Real stiffness(const Params& p) { return p.stiffness; }
  static Real damping(const Params& p) { return p.damping; }
};

}  // namespace maille
