// The body of vbd_begin_shader (src/gpu/gpu_vbd_shaders.cpp, which puts the kernel's head, buffers
// and laws before it).
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
    vec3 vguess = vi + a * u_h;  // (guess - x_n) / h, without the cancellation (below)
    // A point of a contact: within its bound (taken at x_n by the bounds pass before this one),
    // and, with drift balls, within its ball about its prediction x_n + h v_n (the CPU's guard).
    if (u_guarded) {
      uint w = vc_guard(i);
      vec3 centre = xi + vi * u_h;
      vbd_contacts[w + 1u] = floatBitsToUint(centre.x);
      vbd_contacts[w + 2u] = floatBitsToUint(centre.y);
      vbd_contacts[w + 3u] = floatBitsToUint(centre.z);
    }
    vec3 move = vi * u_h + a * (u_h * u_h), held = vc_within_bound(i, move);
    if (u_guarded) held = vc_hold(i, xi, xi + held) - xi;
    if (held != move) {
      guess = xi + held;
      vguess = held * (1.0 / u_h);
    }
    STORE3(x, i, guess);
    STORE3(v, i, vguess);
  }
  STORE3(vbd_y, i, y);
  STORE3(vbd_prev1, i, guess);
}
