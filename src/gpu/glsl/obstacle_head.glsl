// The geometric obstacle's uniforms and the velocity relative to its surface, shared by its
// kernels (src/gpu/gpu_obstacle_shaders.cpp).
uniform uint u_shape;             // ShapeKind (the law's kShape* numbers)
uniform float u_shape_parameter;  // the shape's parameter (a cone's top, a torus's tube)
uniform mat3 u_direct;            // M_d at t
uniform mat3 u_inverse;           // M_i at t
uniform vec3 u_translation;       // m, at t
uniform float u_stiffness;        // k, N/m
uniform float u_damping;          // z, N.s/m
uniform bool u_world_normal;
uniform float u_friction;         // mu
uniform float u_slip;             // m/s: friction is viscous below
uniform float u_reach2;           // m^2: points farther from u_translation touch nothing
uniform bool u_moves;             // the surface's velocity field below is not zero
uniform vec3 u_linear;            // m/s
uniform vec3 u_spin;              // rad/s
uniform vec3 u_spin_center;       // m
vec3 ob_relative_velocity(vec3 xp, vec3 vp) {
  return u_moves ? vp - (u_linear + cross(u_spin, xp - u_spin_center)) : vp;
}
bool ob_far(vec3 xp) {
  vec3 rel = xp - u_translation;
  return dot(rel, rel) > u_reach2;
}
