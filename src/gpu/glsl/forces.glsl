// The body of forces_shader (src/gpu/shaders.cpp, which puts the kernel's head, buffers and laws
// before it).
uniform vec3 u_gravity;  // m/s^2
uniform float u_drag;    // 1/s
uniform bool u_wind;     // face forces to sum
uniform uint u_base;     // the first point of this dispatch (the structured layout runs grids)
void main() {
  if (gl_GlobalInvocationID.x >= u_count) return;
  uint i = u_base + gl_GlobalInvocationID.x;
  vec3 xi = LOAD3(x, i);
  vec3 vi = LOAD3(v, i);
  vec3 fi = vec3(0.0);
  uint end = adjacency_offset[i + 1u];
  for (uint e = adjacency_offset[i]; e < end; ++e) {
    Neighbour n = neighbour(e);
    // The law gives the force on the link's a end; its b end gets the opposite.
    if (n.b_end)
      fi -= link_force(n.kind, n.x, xi, n.v, vi, n.p);
    else
      fi += link_force(n.kind, xi, n.x, vi, n.v, n.p);
  }
  if (u_wind) {
    uint face_end = face_offset[i + 1u];
    for (uint e = face_offset[i]; e < face_end; ++e) fi += LOAD3(face_force, face_of_point[e]);
  }
  if (inv_mass[i] > 0.0) fi += (u_gravity - vi * u_drag) * mass[i];
  STORE3(f, i, fi);
}
