// Friction between two points: the falling friction curve of bowed-string models (a bow's hair
// on a string), acting on the velocity of b relative to a, whatever their distance:
//
//   w = v_b - (v_a + u),  s = |w|,  mu(s) = mu_d + (mu_s - mu_d) v0 / (v0 + s)
//   f_a = N mu(s) w / sqrt(s^2 + eps^2)          (b receives -f_a: it is held back)
//
//   |f|  N mu_s +    .
//               |  .   `  .   stick: viscous, slope N mu_s / eps, below eps
//               | .          ` - . _  slip: falls toward N mu_d as s grows (negative
//        N mu_d +.                   ` ` - - - -   damping: what keeps a string sounding)
//               +--+----------------------------- s
//                  eps
//
// An explicit scheme resolves the stick only as this steep viscous law: the stability estimate
// counts N mu_s / eps as the link's damping (leapfrog needs h < 2 m eps / (N mu_s) on the
// rubbed mass). Drive `a` (a driven fixed point moving at the bow's speed) to bow `b`, or give
// the hair a velocity u of its own (hair_vx, hair_vy, hair_vz; default 0) with `a` at rest: a
// bow whose speed can change while it plays (`maille play`'s controls), since moving the hair
// moves no point. The
// force does no work on a closed path and stores none: energy() is 0. CPU only (no shared law:
// the GPU backend refuses it by name); no Jacobian (implicit Euler refuses it).
#pragma once

#include <array>
#include <cmath>

#include "maille/link_kind.hpp"

namespace maille {

struct Friction {
  static constexpr std::string_view keyword = "friction";
  struct Params {
    Real normal_force = 1;        // N, N: how hard the bow presses, > 0
    Real static_friction = 0.8;   // mu_s, the coefficient when sticking, >= 0
    Real dynamic_friction = 0.3;  // mu_d, the coefficient at high sliding speed, >= 0
    Real velocity_scale = 0.2;    // v0, m/s: how fast mu falls from mu_s to mu_d, > 0
    Real stick_velocity = 0.05;   // eps, m/s: below it the law is viscous, > 0
    Real hair_vx = 0, hair_vy = 0, hair_vz = 0;  // u, m/s: the hair's velocity relative to a
  };
  static constexpr std::array<ParamField<Params>, 8> fields{{
      {"normal_force", "N", &Params::normal_force, Bound::positive, {}, false, "N"},
      {"static_friction", "", &Params::static_friction, Bound::non_negative, Real(0.8), false,
       "mu_s"},
      {"dynamic_friction", "", &Params::dynamic_friction, Bound::non_negative, Real(0.3), false,
       "mu_d"},
      {"velocity_scale", "m/s", &Params::velocity_scale, Bound::positive, Real(0.2), false, "v0"},
      {"stick_velocity", "m/s", &Params::stick_velocity, Bound::positive, Real(0.05), false, "eps"},
      {"hair_vx", "m/s", &Params::hair_vx, Bound::any, Real(0), false, "u_x"},
      {"hair_vy", "m/s", &Params::hair_vy, Bound::any, Real(0), false, "u_y"},
      {"hair_vz", "m/s", &Params::hair_vz, Bound::any, Real(0), false, "u_z"},
  }};

  static Real coefficient(Real s, const Params& p) {
    return p.dynamic_friction +
           (p.static_friction - p.dynamic_friction) * p.velocity_scale / (p.velocity_scale + s);
  }
  static Vec3 force(const Vec3&, const Vec3&, const Vec3& va, const Vec3& vb, const Params& p) {
    const Vec3 w = vb - (va + Vec3{p.hair_vx, p.hair_vy, p.hair_vz});
    const Real s2 = dot(w, w), s = std::sqrt(s2);
    return w * (p.normal_force * coefficient(s, p) /
                std::sqrt(s2 + p.stick_velocity * p.stick_velocity));
  }
  static Real energy(const Vec3&, const Vec3&, const Params&) { return 0; }
  static Real stiffness(const Params&) { return 0; }
  static Real damping(const Params& p) {
    return p.normal_force * std::max(p.static_friction, p.dynamic_friction) / p.stick_velocity;
  }
};

}  // namespace maille
