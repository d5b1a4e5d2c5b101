// The body of obstacle_contacts_shader (src/gpu/gpu_obstacle_shaders.cpp, which puts the kernel's
// head, buffers and laws before it).
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
  vec3 force = obstacle_contact_law(int(u_shape), u_shape_parameter, u_direct, u_inverse,
                                    u_translation, xp, vr, u_stiffness, u_damping,
                                    u_world_normal, u_friction, u_slip, 0.0, false, 0.0,
                                    vec3(0.0), depth, normal, normal_force, stiffness, rubbing);
  if (depth <= 0.0 && !rubbing) return;
  STORE3(f, p, LOAD3(f, p) + force);
}
