// The built-in link kinds' force laws, written once and compiled twice. This file is valid C++
// and valid GLSL 4.50: include/maille/shared_laws.hpp includes it in namespace
// maille::law with `vec3` = Vec3 and `real` = Real (double by default), and the GPU backend's
// force shader (src/gpu/shaders.cpp) pastes its text after defining `real` as float. The CPU
// kinds (include/maille/links/*.hpp) call these functions, so the CPU is the GPU's oracle and a
// law is never copied (the habit of Jolt's shared shader headers).
//
// Rules for this file (as for smooth_math.glsl): no `inline`, `const&`, templates, brace
// initialisers or `f` literals (the scalar type changes); scalars written real(...); every
// parameter used or passed to MAILLE_UNUSED; zero3() for the zero vector; outer3(a, b) and
// identity3() for matrices (mat3 is symmetric-safe only: see the Jacobians below).
//
// A law's signature is (xa, xb, va, vb, then the kind's scene fields in their declared order):
// the GPU backend calls it with the link's parameters as stored, in that order. It returns the
// force on a; b receives its opposite.

// Lengths below this are treated as zero: adding it to |d| keeps 1/|d| finite (a zero-length
// link gets n = 0 and a finite force, never NaN) and changes no length above 1e-15 m by more than
// rounding (float's smallest normal is 1.2e-38, so it is not zero in GLSL either). Branch-free on
// purpose: a compare-and-select or fmax here blocked GCC 12's vectoriser on the link loops.
MAILLE_SHARED real inverse_length(vec3 d) {
  return real(1) / (sqrt(dot(d, d)) + real(1e-30));
}

// Spring (Hooke): f_a = k (|d| - L0) d/|d|, d = x_b - x_a, written k (1 - L0/|d|) d (one
// division, no normalisation).
MAILLE_SHARED vec3 spring_law(vec3 xa, vec3 xb, vec3 va, vec3 vb, real k, real rest) {
  MAILLE_UNUSED(va);
  MAILLE_UNUSED(vb);
  vec3 d = xb - xa;
  return d * (k * (real(1) - rest * inverse_length(d)));
}

// Axial damper: f_a = z ((v_b - v_a).n) n. Axial so that a rigid rotation is not damped.
MAILLE_SHARED vec3 damper_law(vec3 xa, vec3 xb, vec3 va, vec3 vb, real z) {
  vec3 n = (xb - xa) * inverse_length(xb - xa);
  return n * (z * dot(vb - va, n));
}

// Spring and axial damper in parallel, sharing one direction:
//   f_a = [k (|d| - L0) + z (v_b - v_a).n] n = [k (1 - L0/|d|) + z (dv.d)/|d|^2] d.
MAILLE_SHARED vec3 spring_damper_law(vec3 xa, vec3 xb, vec3 va, vec3 vb, real k, real rest,
                                     real z) {
  vec3 d = xb - xa;
  real inv = inverse_length(d);
  return d * (k * (real(1) - rest * inv) + z * dot(vb - va, d) * inv * inv);
}

// ---------------------------------------------------------------------------------------------
// Jacobians (implicit Euler; vertex block descent on the CPU and the GPU). A law's derivative
// d f_a / d x_b (and d f_a / d v_b): the force depends on x_b - x_a and v_b - v_a only, so the
// block at either end, -d f_i / d x_i, is the same matrix. `mat3` is Mat3 in C++ (row-major) and
// GLSL's (column-major): every block here is symmetric, so the two agree. outer3(a, b) = a b^T,
// identity3() = I.

// d/dd of k (|d| - L0) d/|d|:  k [ n n^T + (1 - L0/|d|) (I - n n^T) ]. `definite` clamps the
// transverse factor at 0 (a compressed spring would otherwise contribute a negative stiffness
// and the implicit system could lose definiteness; Choi & Ko 2002).
MAILLE_SHARED mat3 spring_dx(vec3 d, real k, real rest, bool definite) {
  real inv = inverse_length(d);
  vec3 n = d * inv;
  real transverse = real(1) - rest * inv;
  if (definite && transverse < real(0)) transverse = real(0);
  mat3 nn = outer3(n, n);
  return (nn + (identity3() - nn) * transverse) * k;
}

// d/d(dv) of the axial damper z ((v_b - v_a).n) n: z n n^T. (Its d/dd, from the turning of n,
// is not symmetric and is dropped in definite mode, as Baraff & Witkin do: C++ only.)
MAILLE_SHARED mat3 axial_dv(vec3 d, real z) {
  vec3 n = d * inverse_length(d);
  return outer3(n, n) * z;
}

// Each kind's block for vertex block descent: J_x + J_v / h in definite mode (velocities follow
// positions as v = (x - x_n) / h), named <law>_block with the law's arguments then 1/h. The GPU
// backend runs a kind under implicit Euler when its law has such a block.
MAILLE_SHARED mat3 spring_law_block(vec3 xa, vec3 xb, vec3 va, vec3 vb, real k, real rest,
                                    real inv_h) {
  MAILLE_UNUSED(va);
  MAILLE_UNUSED(vb);
  MAILLE_UNUSED(inv_h);
  return spring_dx(xb - xa, k, rest, true);
}

MAILLE_SHARED mat3 damper_law_block(vec3 xa, vec3 xb, vec3 va, vec3 vb, real z, real inv_h) {
  MAILLE_UNUSED(va);
  MAILLE_UNUSED(vb);
  return axial_dv(xb - xa, z) * inv_h;
}

MAILLE_SHARED mat3 spring_damper_law_block(vec3 xa, vec3 xb, vec3 va, vec3 vb, real k, real rest,
                                           real z, real inv_h) {
  MAILLE_UNUSED(va);
  MAILLE_UNUSED(vb);
  return spring_dx(xb - xa, k, rest, true) + axial_dv(xb - xa, z) * inv_h;
}

// Zero while inactive (at or beyond the threshold, as conditional_law decides).
MAILLE_SHARED mat3 conditional_law_block(vec3 xa, vec3 xb, vec3 va, vec3 vb, real k, real z,
                                         real s, real rest, real inv_h) {
  MAILLE_UNUSED(va);
  MAILLE_UNUSED(vb);
  vec3 d = xb - xa;
  if (sqrt(dot(d, d)) >= s) return identity3() * real(0);
  return spring_dx(d, k, rest, true) + axial_dv(d, z) * inv_h;
}

// Conditional spring-damper (the CORDIS contact): silent at or beyond the threshold s, a
// spring-damper toward L0 while closer.
MAILLE_SHARED vec3 conditional_law(vec3 xa, vec3 xb, vec3 va, vec3 vb, real k, real z, real s,
                                   real rest) {
  vec3 d = xb - xa;
  real len = sqrt(dot(d, d));
  if (len >= s) return zero3();
  vec3 n = d * (real(1) / (len + real(1e-30)));
  return n * (k * (len - rest) + z * dot(vb - va, n));
}

// The self-collision contact (the self_collision stage on the CPU and the GPU's grid): two
// particles closer than the contact distance s (the broad phase has tested |d| < s: no threshold
// here) are pushed apart by a spring-damper toward s along n = d / |d|. Rest length s keeps the
// force continuous at s. Returns the force on a; b gets the opposite.
MAILLE_SHARED vec3 contact_normal_law(vec3 xa, vec3 xb, vec3 va, vec3 vb, real k, real z, real s) {
  vec3 d = xb - xa;
  real len = sqrt(dot(d, d));
  vec3 n = d * (real(1) / (len + real(1e-30)));
  return n * (k * (len - s) + z * dot(vb - va, n));
}

// Its Coulomb-like friction on a: mu |F_n . n| along the tangential relative velocity
// v_t = dv - (dv . n) n (dv = v_b - v_a, fn the normal force from contact_normal_law). Below the
// sliding speed `slip` it turns viscous (the force scales with |v_t| / slip) instead of
// chattering around v_t = 0.
MAILLE_SHARED vec3 contact_friction_law(vec3 xa, vec3 xb, vec3 va, vec3 vb, vec3 fn, real mu,
                                        real slip) {
  vec3 d = xb - xa;
  real len = sqrt(dot(d, d));
  vec3 n = d * (real(1) / (len + real(1e-30)));
  vec3 dv = vb - va;
  vec3 vt = dv - n * dot(dv, n);
  real speed = sqrt(dot(vt, vt));
  return vt * (mu * abs(dot(fn, n)) / max(speed, slip));
}

// Friction lagged into an implicit solve (IPC's form; self-collision's point pairs under the
// implicit solvers, src/collision/self/self_contact_link.hpp, and the GPU's VBD): the normal n
// (from a to b) and the normal force's size F_n of the step's start are held, so the friction
// -mu F_n v_t / max(|v_t|, slip) on a (v_t the part of v_b - v_a across n) is a smooth term of
// the solve. Returns its scale mu F_n / max(|v_t|, slip) (0 without friction): the force on a is
// v_t times it, its velocity Jacobian the scale times (I - n n^T).
MAILLE_SHARED real lagged_friction_scale(vec3 va, vec3 vb, vec3 n, real mu, real lag_force,
                                         real slip) {
  if (!(lag_force > real(0) && mu > real(0))) return real(0);
  vec3 dv = vb - va;
  vec3 vt = dv - n * dot(dv, n);
  return mu * lag_force / max(sqrt(dot(vt, vt)), slip);
}

// That friction's force on a at scale `scale` (lagged_friction_scale): v_t times the scale.
MAILLE_SHARED vec3 lagged_friction_force(vec3 va, vec3 vb, vec3 n, real scale) {
  vec3 dv = vb - va;
  return (dv - n * dot(dv, n)) * scale;
}

// Its block J_v / h: the scale times (I - n n^T), over h.
MAILLE_SHARED mat3 lagged_friction_block(vec3 n, real scale, real inv_h) {
  return (identity3() - outer3(n, n)) * (scale * inv_h);
}
