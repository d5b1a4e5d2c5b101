// Conditional (thresholded) spring-damper: silent while the distance is at or beyond its
// threshold, a spring-damper toward `rest_length` (default: the threshold, so the force is
// continuous) while closer. The CORDIS contact brick: it works between any two points.
//
// The distance is a policy: `Distance::separation(xa, xb)` returns the length and unit direction
// the law acts along, `Distance::within(xa, xb, s)` the cheap activity test, and
// `Distance::keyword` names the instantiation in scenes and registries (so a second policy does
// not collide with the first). Point-to-point contact uses the Euclidean one. The Jacobian (for
// implicit schemes) is the Euclidean distance's: only that policy provides it, so implicit
// Euler refuses a model with another policy's links, naming the kind, rather than integrate
// them with a Jacobian of the wrong distance. Geometric contacts (a point against a canonical
// shape through affine maps) are not a link kind but a stage (`geometric_contacts`,
// geometric_point.hpp): their law needs the geometric point's shape and maps at each step; see
// docs/architecture.md, "Decision notes".
#pragma once

#include <array>
#include <concepts>

#include "maille/links/spring_damper.hpp"

namespace maille {

struct EuclideanDistance {
  static constexpr std::string_view keyword = "conditional";
  static constexpr std::string_view shared_law = "conditional_law";  // link_laws.glsl
  static Separation separation(const Vec3& xa, const Vec3& xb) {
    return maille::separation(xa, xb);
  }
  // Cheap pre-test without the square root.
  static bool within(const Vec3& xa, const Vec3& xb, Real s) { return norm2(xb - xa) < s * s; }
};

// The shared law (link_laws.glsl) of a distance policy: only the Euclidean one has one; another
// policy runs on the CPU only.
template <class Distance>
constexpr std::string_view shared_law_of() {
  if constexpr (requires { Distance::shared_law; })
    return Distance::shared_law;
  else
    return {};
}

template <class Distance = EuclideanDistance>
struct ConditionalSpringDamperT {
  static constexpr std::string_view keyword = Distance::keyword;
  static constexpr std::string_view shared_law = shared_law_of<Distance>();
  struct Params {
    Real stiffness = 0;    // k, N/m
    Real damping = 0;      // z, N.s/m
    Real threshold = 0;    // s, m: active while distance < s
    Real rest_length = 0;  // L0, m (the scene defaults it to the threshold)
  };
  static constexpr std::array<ParamField<Params>, 4> fields{{
      {"stiffness", "N/m", &Params::stiffness, Bound::non_negative, {}, false, "k"},
      {"damping", "N.s/m", &Params::damping, Bound::non_negative, Real(0), false, "z"},
      {"threshold",
       "m",
       &Params::threshold,
       Bound::positive,
       {},
       false,
       "active while the distance is below it"},
      {"rest_length",
       "m",
       &Params::rest_length,
       Bound::non_negative,
       {},
       false,
       "default: the threshold (force continuous at the threshold)",
       "threshold"},
  }};

  static bool is_active(const Vec3& xa, const Vec3& xb, const Params& p) {
    return Distance::within(xa, xb, p.threshold);
  }
  static Vec3 force(const Vec3& xa, const Vec3& xb, const Vec3& va, const Vec3& vb,
                    const Params& p) {
    if constexpr (!shared_law.empty()) {
      return law::conditional_law(xa, xb, va, vb, p.stiffness, p.damping, p.threshold,
                                  p.rest_length);
    } else {
      const Separation s = Distance::separation(xa, xb);
      if (s.length >= p.threshold) return {};
      return spring_damper_force(s, vb - va, p.stiffness, p.rest_length, p.damping);
    }
  }
  // Zero while inactive; a spring-damper toward rest_length while active. The Euclidean policy
  // only: the blocks below differentiate |xb - xa|.
  static LinkJacobian jacobian(
      const Vec3& xa, const Vec3& xb, const Vec3& va, const Vec3& vb, const Params& p,
      JacobianMode mode) requires std::same_as<Distance, EuclideanDistance> {
    if (!Distance::within(xa, xb, p.threshold)) return {};
    LinkJacobian j = damper_jacobian(xb - xa, vb - va, p.damping, mode);
    j.dx += spring_jacobian(xb - xa, p.stiffness, p.rest_length, mode);
    return j;
  }
  static Real energy(const Vec3& xa, const Vec3& xb, const Params& p) {
    const Real d = Distance::separation(xa, xb).length;
    if (d >= p.threshold) return 0;
    const Real e = d - p.rest_length;
    return Real(0.5) * p.stiffness * e * e;
  }
  static Real stiffness(const Params& p) { return p.stiffness; }
  static Real damping(const Params& p) { return p.damping; }
};

using ConditionalSpringDamper = ConditionalSpringDamperT<>;

}  // namespace maille
