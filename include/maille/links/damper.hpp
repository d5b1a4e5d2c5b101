// Damper ("frein"), an axial dashpot: f_a = z ((v_b - v_a).n) n,  n = (x_b - x_a)/|x_b - x_a|.
// Axial rather than isotropic so that a rigid rotation is not damped (angular momentum is kept).
#pragma once

#include <array>

#include "maille/links/spring.hpp"

namespace maille {

struct Damper {
  static constexpr std::string_view keyword = "damper";
  static constexpr std::string_view shared_law = "damper_law";  // link_laws.glsl
  struct Params {
    Real damping = 0;  // z, N.s/m
  };
  static constexpr std::array<ParamField<Params>, 1> fields{{
      {"damping", "N.s/m", &Params::damping, Bound::non_negative, {}, false, "z"},
  }};

  static Vec3 force(const Vec3& xa, const Vec3& xb, const Vec3& va, const Vec3& vb,
                    const Params& p) {
    return law::damper_law(xa, xb, va, vb, p.damping);
  }
  static LinkJacobian jacobian(const Vec3& xa, const Vec3& xb, const Vec3& va, const Vec3& vb,
                               const Params& p, JacobianMode mode) {
    return damper_jacobian(xb - xa, vb - va, p.damping, mode);
  }
  static Real energy(const Vec3&, const Vec3&, const Params&) { return 0; }
  static Real stiffness(const Params&) { return 0; }
  static Real damping(const Params& p) { return p.damping; }
};

}  // namespace maille
