// Internal: self-collision's point-point contacts as links for implicit solvers (the stage's
// transient pool, self_collision_stage.cpp), with their friction lagged into the solve.
#pragma once

#include <algorithm>
#include <array>
#include <limits>

#include "maille/links/conditional.hpp"
#include "maille/self_collision.hpp"
#include "maille/shared_laws.hpp"

namespace maille::collision {

// The conditional spring-damper of a contact (active within the radius s) and its Coulomb
// friction, lagged (IPC's form, as obstacles do): the normal n and the normal force's size F_n
// are those of the step's start, held through the solve, so the friction is a smooth term of
// the solve, -mu F_n v_t / max(|v_t|, slip) on a (v_t the tangential part of v_b - v_a across the
// held n), with the block (mu F_n / max(|v_t|, slip)) (I - n n^T) / h, its scale held. A pair
// that was in contact at the step's start keeps its friction while the solve moves it apart (the
// friction of that step), as the explicit step would. Not a scene kind: the stage fills a pool
// of it each step.
struct FrictionalContact {
  static constexpr std::string_view keyword = "self_contact";
  using Normal = ConditionalSpringDamper;
  struct Params {
    Normal::Params normal;  // k, z, s, rest length (= s)
    Real friction = 0;      // mu
    Real lag_force = 0;     // |F_n| at the step's start (0: no friction this step)
    Vec3 lag_normal;        // n at the step's start, from a to b
  };
  // The conditional kind's fields (what tools list); friction and the lag are the stage's.
  static constexpr std::array<ParamField<Params>, 0> fields{};

  static bool is_active(const Vec3& xa, const Vec3& xb, const Params& p) {
    return p.lag_force > 0 || Normal::is_active(xa, xb, p.normal);
  }
  // The distance below which the link may act (LinkPool::near_slots): the contact radius, or
  // anywhere while its lagged friction acts.
  static Real reach(const Params& p) {
    return p.lag_force > 0 ? std::numeric_limits<Real>::infinity() : p.normal.threshold;
  }
  static Vec3 friction_force(const Vec3& va, const Vec3& vb, const Params& p, Real& scale) {
    scale = law::lagged_friction_scale(va, vb, p.lag_normal, p.friction, p.lag_force,
                                       kSelfCollisionSlip);
    if (!(scale > 0)) return {};
    return law::lagged_friction_force(va, vb, p.lag_normal, scale);
  }
  static Vec3 force(const Vec3& xa, const Vec3& xb, const Vec3& va, const Vec3& vb,
                    const Params& p) {
    Real scale;
    return Normal::force(xa, xb, va, vb, p.normal) + friction_force(va, vb, p, scale);
  }
  static LinkJacobian jacobian(const Vec3& xa, const Vec3& xb, const Vec3& va, const Vec3& vb,
                               const Params& p, JacobianMode mode) {
    LinkJacobian j = Normal::jacobian(xa, xb, va, vb, p.normal, mode);
    Real scale;
    friction_force(va, vb, p, scale);
    if (scale > 0) j.dv += law::lagged_friction_block(p.lag_normal, scale, Real(1));  // J_v
    return j;
  }
  static Real energy(const Vec3& xa, const Vec3& xb, const Params& p) {
    return Normal::energy(xa, xb, p.normal);
  }
  static Real stiffness(const Params& p) { return p.normal.stiffness; }
  static Real damping(const Params& p) { return p.normal.damping; }
};

}  // namespace maille::collision
