// The body of vbd_accelerate_shader (src/gpu/gpu_vbd_shaders.cpp, which puts the kernel's head,
// buffers and laws before it).
uniform float u_omega;
uniform float u_h;          // s
uniform bool u_extrapolate; // the second sweep on
uniform float u_thinnest;   // m: the thinnest obstacle (+inf: none, or planes only)
void main() {
  uint i = gl_GlobalInvocationID.x;
  if (i >= u_count || vbd_state[0] == 0u || inv_mass[i] == 0.0) return;
  vec3 xi = LOAD3(x, i);
  // The shared rule (contact_laws.glsl): the place, and whether the point takes the jump (v
  // follows it, as in the sweep); nor out of its drift ball, as on the CPU.
  vec3 to = chebyshev_place(xi, LOAD3(vbd_prev2, i), u_omega);
  if (u_extrapolate && chebyshev_takes(vbd_touch[i] != 0u, vc_bounded(i), to - xi,
                                       0.5 * u_thinnest) && vc_inside(i, to)) {
    STORE3(v, i, LOAD3(v, i) + (to - xi) * (1.0 / u_h));
    xi = to;
    STORE3(x, i, xi);
  }
  STORE3(vbd_prev2, i, xi);
}
