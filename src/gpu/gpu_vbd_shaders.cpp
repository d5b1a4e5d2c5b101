// The GPU's vertex block descent kernels (gpu_vbd.hpp has the passes): the CPU solver's
// arithmetic (src/integrators/implicit_vbd.cpp) in float, the links' forces and blocks from the
// shared laws (include/maille/detail/link_laws.glsl).
#include <string>

#include "gpu_vbd.hpp"
#include "gpu_vbd_obstacles.hpp"
#include "shared_laws_glsl.hpp"

namespace maille::gpu {

namespace {

// `mat3 link_block(uint kind, vec3 xa, vec3 xb, vec3 va, vec3 vb, vec4 p, float inv_h)`: kind k
// calls its law's block (<law>_block) with its first `fields` parameters and 1/h.
std::string link_block_function(const std::vector<KindLaw>& kinds) {
  return link_switch_function(kinds, {"mat3", "link_block", "_block", ", float inv_h", ", inv_h"});
}

}  // namespace

std::string vbd_begin_shader() {
  std::string s =
      kernel_head({Buf::x, Buf::v, Buf::mass, Buf::inv_mass, Buf::face_offset, Buf::face_of_point,
                   Buf::face_force, Buf::vbd_xn, Buf::vbd_y, Buf::vbd_vlast, Buf::vbd_prev1});
  s += R"(
uniform vec3 u_gravity;  // m/s^2
uniform float u_h;       // s
uniform bool u_wind;     // face forces to sum
uniform bool u_history;  // vbd_vlast holds v at the last step's start
void main() {
  uint i = gl_GlobalInvocationID.x;
  if (i >= u_count) return;
  vec3 xi = LOAD3(x, i);
  vec3 vi = LOAD3(v, i);
  vec3 vlast = LOAD3(vbd_vlast, i);
  STORE3(vbd_xn, i, xi);
  STORE3(vbd_vlast, i, vi);
  float w = inv_mass[i];
  vec3 y = xi, guess = xi;
  if (w > 0.0) {
    // f_ext: what the solve does not take implicitly (gravity and wind, at the step's start).
    vec3 fext = u_gravity * mass[i];
    if (u_wind) {
      uint face_end = face_offset[i + 1u];
      for (uint e = face_offset[i]; e < face_end; ++e) fext += LOAD3(face_force, face_of_point[e]);
    }
    y = xi + vi * u_h + fext * (u_h * u_h * w);
    // The paper's adaptive guess: along a_ext, last step's acceleration within [0, |a_ext|].
    vec3 a_ext = fext * w;
    vec3 a = a_ext;
    if (u_history) {
      vec3 a_last = (vi - vlast) * (1.0 / u_h);
      float len = length(a_ext);
      a = len > 0.0 ? a_ext * (clamp(dot(a_last, a_ext) / len, 0.0, len) / len) : vec3(0.0);
    }
    guess = xi + vi * u_h + a * (u_h * u_h);
    STORE3(x, i, guess);
    STORE3(v, i, vi + a * u_h);  // (guess - x_n) / h, without the cancellation (below)
  }
  STORE3(vbd_y, i, y);
  STORE3(vbd_prev1, i, guess);
}
)";
  return s;
}

// One colour's Newton steps (or, with `residual`, the imbalance at the result over every free
// point, moving none): g_i = m/h^2 (y - x) - gamma m v + links' forces + obstacles', H_i =
// m (1/h^2 + gamma/h) I + links' blocks + obstacles'. A step that starts or leaves an obstacle's
// contact follows the CPU's rules (gpu_vbd_obstacles.hpp).
std::string vbd_sweep_shader(const std::vector<KindLaw>& kinds, bool residual) {
  std::string s =
      kernel_head({Buf::x, Buf::v, Buf::mass, Buf::adjacency_offset, Buf::adjacency,
                   Buf::link_params, Buf::vbd_xn, Buf::vbd_y, Buf::vbd_order, Buf::vbd_state,
                   Buf::vbd_obstacles, Buf::vbd_ob_member, Buf::vbd_ob_lag, Buf::vbd_touch});
  s += shared::link_laws;
  s += vbd_obstacle_functions();
  s += link_force_function(kinds);
  s += link_block_function(kinds);
  s += residual ? "#define RESIDUAL 1\n" : "#define RESIDUAL 0\n";
  s += "#define GROUP " + std::to_string(kGroupSize) + "u\n";
  s += R"(
uniform uint u_first;  // the colour's first entry in vbd_order
uniform uint u_slot;   // the colour's first work group among the sweep's (vbd_state[8 + slot])
uniform float u_h;     // s
uniform float u_drag;  // 1/s
shared float s_sum[GROUP];
void main() {
  uint t = gl_LocalInvocationID.x;
  uint k = gl_GlobalInvocationID.x;
  float merit = 0.0;  // the residual pass: |g|; a sweep: g . H^-1 g (the CPU's merit)
  if (k < u_count) {
    uint i = vbd_order[u_first + k];
    float inv_h = 1.0 / u_h;
    float inv_h2 = inv_h * inv_h;
    float m = mass[i];
    vec3 xi = LOAD3(x, i);
    vec3 vi = LOAD3(v, i);
    vec3 g = (LOAD3(vbd_y, i) - xi) * (m * inv_h2) - vi * (u_drag * m);
    mat3 H = mat3(m * (inv_h2 + u_drag * inv_h));
    uint end = adjacency_offset[i + 1u];
    for (uint e = adjacency_offset[i]; e < end; ++e) {
      Adjacent l = adjacency[e];
      vec3 xj = LOAD3(x, l.other);
      vec3 vj = LOAD3(v, l.other);
      vec4 p = vec4(link_params[4u * l.params], link_params[4u * l.params + 1u],
                    link_params[4u * l.params + 2u], link_params[4u * l.params + 3u]);
      // The law gives the force on the link's a end (b gets the opposite); the block is the
      // same at both ends.
      if ((l.kind & 0x80000000u) != 0u) {
        uint kind = l.kind & 0x7fffffffu;
        g -= link_force(kind, xj, xi, vj, vi, p);
        H += link_block(kind, xj, xi, vj, vi, p, inv_h);
      } else {
        g += link_force(l.kind, xi, xj, vi, vj, p);
        H += link_block(l.kind, xi, xj, vi, vj, p, inv_h);
      }
    }
    bool touching = ob_terms(i, xi, vi, inv_h, g, H);
#if RESIDUAL
    merit = length(g);
#else
    float det = determinant(H);
    vec3 dx = abs(det) > 0.0 ? inverse(H) * g : g;
    // Non-finite: left to the health check (the CPU does the same).
    // v = (x - x_n) / h, kept as v += dx / h: the difference of two float positions loses
    // eps |x| / h (2e-5 m/s at 3 m and 1/120 s), which the explicit wind, a function of v, then
    // amplifies; the increment keeps v's own relative precision.
    bool touched = touching;  // the CPU's touching_[i] after the update
    if (!(any(isnan(dx)) || any(isinf(dx)))) {
      merit = dot(g, dx);
      vec3 tx = xi + dx, tv = vi + dx * inv_h, tg;
      vec3 xn = LOAD3(vbd_xn, i);
      // Same contacts, or leaving one cleanly: the whole step. Starting or (far) leaving one:
      // the step stops just inside the surface (bisection), touching.
      bool trial_touch = u_obstacles > 0u && ob_touches(i, tx, tv, inv_h, tg);
      if (trial_touch == touching || (touching && ob_leaves_cleanly(i, xi, tx, xn))) {
        STORE3(x, i, tx);
        STORE3(v, i, tv);
      } else {
        vec2 change = ob_contact_change(i, xi, dx, xn, inv_h, touching);
        vec3 xs = xi + dx * (touching ? change.x : change.y);
        STORE3(x, i, xs);
        STORE3(v, i, (xs - xn) * inv_h);
        touched = true;
      }
    }
    vbd_touch[i] = touched ? 1u : 0u;
#endif
  }
  // The residual: the largest |g| of the work group, then of the dispatch (non-negative floats
  // order as their bits do). A sweep: the work group's sum of g . H^-1 g, into its own slot
  // (the decide pass adds the slots in order: the same sum on every run).
  s_sum[t] = merit;
  barrier();
  for (uint half_ = GROUP / 2u; half_ > 0u; half_ >>= 1u) {
    if (t < half_) s_sum[t] = RESIDUAL != 0 ? max(s_sum[t], s_sum[t + half_])
                                            : s_sum[t] + s_sum[t + half_];
    barrier();
  }
  if (t == 0u) {
#if RESIDUAL
    atomicMax(vbd_state[4], floatBitsToUint(s_sum[0]));
#else
    vbd_state[8u + u_slot + gl_WorkGroupID.x] = floatBitsToUint(s_sum[0]);
#endif
  }
}
)";
  return s;
}

// The CPU's fallback (implicit_vbd.cpp, kFallbackGrowth): from the third sweep on, a sweep
// whose merit (the sum of g . H^-1 g, the work groups' slots added in order) more than doubled
// turns the acceleration off for the rest of the step.
std::string vbd_decide_shader() {
  std::string s = kernel_head({Buf::vbd_state});
  s += R"(
uniform uint u_k;      // the sweep just run, from 1
uniform uint u_slots;  // the sweep's work groups
uniform float u_growth;
void main() {
  if (gl_GlobalInvocationID.x != 0u) return;
  float merit = 0.0;
  for (uint s_ = 0u; s_ < u_slots; ++s_) merit += uintBitsToFloat(vbd_state[8u + s_]);
  if (vbd_state[0] != 0u && u_k >= 3u && merit > u_growth * uintBitsToFloat(vbd_state[2])) {
    vbd_state[0] = 0u;
    vbd_state[3] += 1u;
  }
  vbd_state[2] = floatBitsToUint(merit);
}
)";
  return s;
}

// Chebyshev: x = w (x - x_prev2) + x_prev2 from the second sweep on, except (the CPU's rules)
// for points touching an obstacle and jumps longer than half the thinnest obstacle; then the
// sweep's x into the buffer that the host names prev1 next.
std::string vbd_accelerate_shader() {
  std::string s = kernel_head(
      {Buf::x, Buf::v, Buf::inv_mass, Buf::vbd_xn, Buf::vbd_prev2, Buf::vbd_state, Buf::vbd_touch});
  s += R"(
uniform float u_omega;
uniform float u_h;          // s
uniform bool u_extrapolate; // the second sweep on
uniform float u_thinnest;   // m: the thinnest obstacle (+inf: none, or planes only)
void main() {
  uint i = gl_GlobalInvocationID.x;
  if (i >= u_count || vbd_state[0] == 0u || inv_mass[i] == 0.0) return;
  vec3 xi = LOAD3(x, i);
  // x = w (x - prev2) + prev2, as the increment (w - 1) (x - prev2) (v follows it, as in the
  // sweep).
  vec3 dx = (xi - LOAD3(vbd_prev2, i)) * (u_omega - 1.0);
  float half_ = 0.5 * u_thinnest;
  if (u_extrapolate && vbd_touch[i] == 0u && dot(dx, dx) <= half_ * half_) {
    xi += dx;
    STORE3(x, i, xi);
    STORE3(v, i, LOAD3(v, i) + dx * (1.0 / u_h));
  }
  STORE3(vbd_prev2, i, xi);
}
)";
  return s;
}

// The obstacles' lagged friction at the step's start (x_n, v_n, placed at t), per point.
std::string vbd_lag_shader() {
  std::string s = kernel_head(
      {Buf::x, Buf::v, Buf::inv_mass, Buf::vbd_obstacles, Buf::vbd_ob_member, Buf::vbd_ob_lag});
  s += vbd_obstacle_functions();
  s += R"(
void main() {
  uint i = gl_GlobalInvocationID.x;
  if (i >= u_count || inv_mass[i] == 0.0) return;
  ob_lag(i, LOAD3(x, i), LOAD3(v, i));
}
)";
  return s;
}

// The CPU's stop_at_first_touch: a point moving more than half the thinnest obstacle from x_n
// stops just inside the first obstacle it enters on the way (the guess, which the acceleration
// then starts from: prev1 too), or, `through_only`, unless it touches at its end (the result).
std::string vbd_first_touch_shader() {
  std::string s = kernel_head({Buf::x, Buf::v, Buf::inv_mass, Buf::vbd_xn, Buf::vbd_prev1,
                               Buf::vbd_obstacles, Buf::vbd_ob_member, Buf::vbd_ob_lag});
  s += vbd_obstacle_functions();
  s += R"(
uniform float u_h;  // s
uniform bool u_through_only;
void main() {
  uint i = gl_GlobalInvocationID.x;
  if (i >= u_count || inv_mass[i] == 0.0) return;
  vec3 xn = LOAD3(vbd_xn, i), xi = LOAD3(x, i), d = xi - xn;
  float half_ = 0.5 * u_thinnest;
  if (dot(d, d) <= half_ * half_) return;
  float inv_h = 1.0 / u_h;
  float t = ob_first_touch(i, xn, xi, inv_h, u_through_only);
  if (t >= 1.0) return;
  vec3 xs = xn + d * t;
  STORE3(x, i, xs);
  STORE3(v, i, (xs - xn) * inv_h);
  if (!u_through_only) STORE3(vbd_prev1, i, xs);
}
)";
  return s;
}

std::string vbd_health_shader() {
  std::string s = kernel_head({Buf::x, Buf::v, Buf::health});
  s += R"(
uniform uint u_step;  // the step count after this step (the health flag's value)
void main() {
  uint i = gl_GlobalInvocationID.x;
  if (i >= u_count) return;
  vec3 xi = LOAD3(x, i);
  vec3 vi = LOAD3(v, i);
  if (any(isnan(xi)) || any(isinf(xi)) || any(isnan(vi)) || any(isinf(vi)))
    atomicMin(health[0], u_step);
}
)";
  return s;
}

}  // namespace maille::gpu
