// The response of inverse dynamics on a facet, as a pure function (docs/obstacles.md
// derives it). With n the facet's outward normal and the velocity taken relative to the facet:
//
//   normal      F_N' = -alpha F_N, V_N' = -alpha V_N   (only the parts heading into the facet:
//               an obstacle pushes, it never pulls; a force leaving the surface is kept)
//   tangential  the static rule on the force: F_T' = 0 when |F_T| < beta |F_N|, else
//               F_T' = (1 - beta |F_N| / |F_T|) F_T; and on the velocity at an impact:
//               V_T' = (1 - beta |V_N| / |V_T|) V_T (zero when that is negative).
//
// For leapfrog and symplectic Euler the velocity the particle leaves with is W = V' + h F' / m,
// so W_N = -alpha (V_N + h F_N / m): alpha is the restitution coefficient of the normal
// velocity (alpha = 0 rests, alpha = 1 rebounds elastically), and with the particle at rest the
// tangential rule is Coulomb's law with coefficient beta (sticks while tan(theta) < beta on an
// incline, slides with g (sin(theta) - beta cos(theta)) otherwise). One addition, where the
// static rule has no answer: a particle already sliding (V_T != 0) is braked against its
// velocity, F_T' = F_T - beta |F_N| V_T / |V_T|, and stops (sticks) rather than reverse when
// static friction can hold it; without it, a particle sliding on a level facet, where F_T = 0,
// would never slow down.
//
// Resting contact. Reflecting the force launches a particle at rest by alpha h |F_N| / m each
// step: it would hop forever over the facet, with no friction while in the air, and creep down
// any incline. So, as rigid-body engines do with a restitution threshold, a contact whose
// approach speed W_N is no more than two steps of its push (2 h |F_N| / m) is a resting one:
// its inward force and velocity are cancelled (the support's reaction) rather than reflected;
// the tangential rules are unchanged. Impacts above that speed follow the alpha law.
#pragma once

#include "maille/vec3.hpp"

namespace maille::facets {

struct Response {
  bool stuck = false;  // no tangential motion leaves the contact this step
};

// `kicked`: the scheme drifts with the velocity after this step's kick (StageContext).
inline Response respond(Vec3& v, Vec3& f, const Vec3& n, const Vec3& surface_velocity,
                        Real inv_mass, Real h, Real alpha, Real beta, bool kicked = true) {
  const Vec3 vr = v - surface_velocity;
  const Real fn = dot(f, n), vn = dot(vr, n);
  const Vec3 f_n = n * fn, v_n = n * vn;
  const Vec3 f_t = f - f_n;
  Vec3 v_t = vr - v_n;
  const Real push = fn < 0 ? -fn : Real(0);  // |F_N| of a force into the facet
  const Real approach = -(vn + (kicked ? h * fn * inv_mass : Real(0)));
  const Real restitution = approach > 2 * h * push * inv_mass ? alpha : Real(0);
  const Vec3 f_n_out = fn < 0 ? f_n * -restitution : f_n;
  const Vec3 v_n_out = vn < 0 ? v_n * -restitution : v_n;
  if (vn < 0) {  // impact friction on the velocity
    const Real vt = norm(v_t);
    v_t = vt > 0 ? v_t * std::max<Real>(0, 1 - beta * -vn / vt) : Vec3{};
  }
  Vec3 f_t_out;
  const Real ft = norm(f_t), vt = norm(v_t);
  bool stuck = false;
  if (vt > Real(1e-12)) {  // sliding: kinetic friction against the velocity
    f_t_out = f_t - v_t * (beta * push / vt);
    const Vec3 w_t = v_t + f_t_out * (h * inv_mass);
    if (dot(w_t, v_t) < 0 && ft <= beta * push) {  // it would reverse: static friction holds
      f_t_out = v_t * (-1 / (h * inv_mass));
      stuck = true;
    }
  } else if (ft < beta * push || ft == 0) {  // the static rule
    f_t_out = {};
    v_t = {};
    stuck = true;
  } else {
    f_t_out = f_t * (1 - beta * push / ft);
  }
  f = f_n_out + f_t_out;
  v = surface_velocity + v_n_out + v_t;
  return {stuck};
}

}  // namespace maille::facets
