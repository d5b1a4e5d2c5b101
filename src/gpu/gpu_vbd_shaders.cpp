// The GPU's vertex block descent kernels (gpu_vbd.hpp has the passes): the CPU solver's
// arithmetic (src/integrators/implicit_vbd.cpp) in float, the links' forces and blocks from the
// shared laws (include/maille/detail/link_laws.glsl).
#include <bit>
#include <cstdint>
#include <cstdio>
#include <string>

#include "gpu_glsl.hpp"
#include "gpu_vbd.hpp"
#include "gpu_vbd_obstacles.hpp"
#include "maille/self_collision.hpp"
#include "shared_laws_glsl.hpp"

namespace maille::gpu {

namespace {

// `mat3 link_block(uint kind, vec3 xa, vec3 xb, vec3 va, vec3 vb, vec4 p, float inv_h)`: kind k
// calls its law's block (<law>_block) with its first `fields` parameters and 1/h.
std::string link_block_function(const std::vector<KindLaw>& kinds) {
  return link_switch_function(kinds, {"mat3", "link_block", "_block", ", float inv_h", ", inv_h"});
}

// A float constant of the C++ as GLSL, bit for bit.
std::string float_literal(float f) {
  char text[40];
  std::snprintf(text, sizeof text, "uintBitsToFloat(0x%08xu)", std::bit_cast<std::uint32_t>(f));
  return text;
}

// vbd_contacts' functions (glsl/vbd_contacts.glsl) with the CPU's constants, after the shared
// laws they call: the contact laws for `geometry` (stencil distances, the drift guard's hold),
// the link laws too for `terms` (the pairs' and stencils' forces and blocks).
std::string contact_functions(bool geometry, bool terms) {
  std::string s = "#define PAIR_WORDS " + std::to_string(kVbdPairWords) + "u\n";
  s += "#define STENCIL_WORDS " + std::to_string(kVbdStencilWords) + "u\n";
  s += "#define BOUND_FRACTION " + float_literal(float(kBoundFraction)) + "\n";
  s += "#define STENCIL_FLOOR " + float_literal(float(kStencilFloor)) + "\n";
  s += "#define SLIP " + float_literal(float(kSelfCollisionSlip)) + "\n";
  if (geometry || terms) s += std::string(shared::contact_laws) + "#define CONTACT_GEOMETRY 1\n";
  if (terms) s += "#define CONTACT_TERMS 1\n";
  s += glsl::vbd_contacts;
  return s;
}

}  // namespace

std::string vbd_begin_shader() {
  return kernel_source(
      {Buf::x, Buf::v, Buf::mass, Buf::inv_mass, Buf::face_offset, Buf::face_of_point,
       Buf::face_force, Buf::vbd_xn, Buf::vbd_y, Buf::vbd_vlast, Buf::vbd_prev1, Buf::vbd_contacts},
      {contact_functions(true, false), glsl::vbd_begin});
}

// One colour's Newton steps (or, with `residual`, the imbalance at the result over every free
// point, moving none): g_i = m/h^2 (y - x) - gamma m v + links' forces + obstacles', H_i =
// m (1/h^2 + gamma/h) I + links' blocks + obstacles'. A step that starts or leaves an obstacle's
// contact follows the CPU's rules (gpu_vbd_obstacles.hpp).
std::string vbd_sweep_shader(const std::vector<KindLaw>& kinds, bool residual) {
  return kernel_source(
      {Buf::x, Buf::v, Buf::mass, Buf::adjacency_offset, Buf::adjacency, Buf::link_params,
       Buf::vbd_xn, Buf::vbd_y, Buf::vbd_order, Buf::vbd_state, Buf::vbd_obstacles,
       Buf::vbd_ob_member, Buf::vbd_ob_lag, Buf::vbd_touch, Buf::vbd_contacts},
      {shared::link_laws, contact_functions(true, true), vbd_obstacle_functions(),
       link_force_function(kinds), link_block_function(kinds),
       residual ? "#define RESIDUAL 1\n" : "#define RESIDUAL 0\n",
       "#define GROUP " + std::to_string(kGroupSize) + "u\n", glsl::adjacency, glsl::vbd_sweep});
}

// The CPU's fallback (implicit_vbd.cpp, kFallbackGrowth): from the third sweep on, a sweep
// whose merit (the sum of g . H^-1 g, the work groups' slots added in order) more than doubled
// turns the acceleration off for the rest of the step.
std::string vbd_decide_shader() {
  return kernel_source({Buf::vbd_state}, {glsl::vbd_decide});
}

// Chebyshev: x = w (x - x_prev2) + x_prev2 from the second sweep on, except (the CPU's rules)
// for points touching an obstacle and jumps longer than half the thinnest obstacle; then the
// sweep's x into the buffer that the host names prev1 next. The contact functions bring the
// shared laws: the Chebyshev rule.
std::string vbd_accelerate_shader() {
  return kernel_source({Buf::x, Buf::v, Buf::inv_mass, Buf::vbd_xn, Buf::vbd_prev2, Buf::vbd_state,
                        Buf::vbd_touch, Buf::vbd_contacts},
                       {contact_functions(true, false), glsl::vbd_accelerate});
}

// The obstacles' lagged friction at the step's start (x_n, v_n, placed at t), per point.
std::string vbd_lag_shader() {
  return kernel_source(
      {Buf::x, Buf::v, Buf::inv_mass, Buf::vbd_obstacles, Buf::vbd_ob_member, Buf::vbd_ob_lag},
      {vbd_obstacle_functions(), glsl::vbd_lag});
}

// The CPU's stop_at_first_touch: a point moving more than half the thinnest obstacle from x_n
// stops just inside the first obstacle it enters on the way (the guess, which the acceleration
// then starts from: prev1 too), or, `through_only`, unless it touches at its end (the result).
std::string vbd_first_touch_shader() {
  return kernel_source({Buf::x, Buf::v, Buf::inv_mass, Buf::vbd_xn, Buf::vbd_prev1,
                        Buf::vbd_obstacles, Buf::vbd_ob_member, Buf::vbd_ob_lag},
                       {vbd_obstacle_functions(), glsl::vbd_first_touch});
}

// Each point's bound at the current x (the CPU's take_bounds over the pairs).
std::string vbd_bounds_shader() {
  return kernel_source({Buf::x, Buf::vbd_contacts},
                       {contact_functions(true, false), glsl::vbd_bounds});
}

std::string vbd_health_shader() {
  return kernel_source({Buf::x, Buf::v, Buf::health}, {glsl::vbd_health});
}

}  // namespace maille::gpu
