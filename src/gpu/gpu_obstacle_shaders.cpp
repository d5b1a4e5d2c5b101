// The geometric obstacle's kernels (gpu_obstacle.hpp): the CPU stage's law, pasted from
// include/maille/detail/obstacle_laws.glsl.
#include "gpu_obstacle.hpp"
#include "shaders.hpp"
#include "shared_laws_glsl.hpp"

namespace maille::gpu {

namespace {

// The obstacle's uniforms and the velocity relative to its surface, shared by its kernels.
const char* kObstacleHead = R"(
uniform uint u_shape;        // ShapeKind
uniform float u_top;         // cone
uniform float u_tube;        // torus
uniform mat3 u_direct;       // M_d at t
uniform mat3 u_inverse;      // M_i at t
uniform vec3 u_translation;  // m, at t
uniform float u_stiffness;   // k, N/m
uniform float u_damping;     // z, N.s/m
uniform bool u_world_normal;
uniform float u_friction;    // mu
uniform float u_slip;        // m/s: friction is viscous below
uniform float u_reach2;      // m^2: points farther from u_translation touch nothing
uniform bool u_moves;        // the surface's velocity field below is not zero
uniform vec3 u_linear;       // m/s
uniform vec3 u_spin;         // rad/s
uniform vec3 u_spin_center;  // m
vec3 ob_relative_velocity(vec3 xp, vec3 vp) {
  return u_moves ? vp - (u_linear + cross(u_spin, xp - u_spin_center)) : vp;
}
bool ob_far(vec3 xp) {
  vec3 rel = xp - u_translation;
  return dot(rel, rel) > u_reach2;
}
)";

}  // namespace

std::string obstacle_contacts_shader() {
  std::string s = kernel_head({Buf::x, Buf::v, Buf::f, Buf::ob_point});
  s += shared::obstacle_laws;
  s += kObstacleHead;
  s += R"(
void main() {
  uint a = gl_GlobalInvocationID.x;
  if (a >= u_count) return;
  uint p = ob_point[a];
  vec3 xp = LOAD3(x, p);
  if (ob_far(xp)) return;
  vec3 vr = ob_relative_velocity(xp, LOAD3(v, p));
  float depth, normal_force;
  vec3 normal;
  mat3 stiffness;
  bool rubbing;
  vec3 force = obstacle_contact_law(int(u_shape), u_top, u_tube, u_direct, u_inverse,
                                    u_translation, xp, vr, u_stiffness, u_damping,
                                    u_world_normal, u_friction, u_slip, 0.0, false, 0.0,
                                    vec3(0.0), depth, normal, normal_force, stiffness, rubbing);
  if (depth <= 0.0 && !rubbing) return;
  STORE3(f, p, LOAD3(f, p) + force);
}
)";
  return s;
}

}  // namespace maille::gpu
