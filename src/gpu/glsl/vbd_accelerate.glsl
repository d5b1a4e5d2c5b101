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
  // x = w (x - prev2) + prev2, as the increment (w - 1) (x - prev2) (v follows it, as in the
  // sweep).
  vec3 dx = (xi - LOAD3(vbd_prev2, i)) * (u_omega - 1.0);
  float half_ = 0.5 * u_thinnest;
  // Not a point touching an obstacle or in a contact (bounded), nor out of its drift ball, as
  // on the CPU.
  if (u_extrapolate && vbd_touch[i] == 0u && !vc_bounded(i) && dot(dx, dx) <= half_ * half_ &&
      vc_inside(i, xi + dx)) {
    xi += dx;
    STORE3(x, i, xi);
    STORE3(v, i, LOAD3(v, i) + dx * (1.0 / u_h));
  }
  STORE3(vbd_prev2, i, xi);
}
