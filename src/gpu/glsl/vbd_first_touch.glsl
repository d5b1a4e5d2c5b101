// The body of vbd_first_touch_shader (src/gpu/gpu_vbd_shaders.cpp, which puts the kernel's head,
// buffers and laws before it).
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
