// The body of vbd_sweep_shader (src/gpu/gpu_vbd_shaders.cpp, which puts the kernel's head, buffers
// and laws before it).
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
      Neighbour n = neighbour(e);
      // The law gives the force on the link's a end (b gets the opposite); the block is the
      // same at both ends.
      if (n.b_end) {
        g -= link_force(n.kind, n.x, xi, n.v, vi, n.p);
        H += link_block(n.kind, n.x, xi, n.v, vi, n.p, inv_h);
      } else {
        g += link_force(n.kind, xi, n.x, vi, n.v, n.p);
        H += link_block(n.kind, xi, n.x, vi, n.v, n.p, inv_h);
      }
    }
    pair_terms(i, xi, vi, inv_h, g, H);
    stencil_terms(i, inv_h, g, H);
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
      dx = vc_within_bound(i, dx);  // a point of a contact: within its bound
      if (u_guarded) dx = vc_hold(i, xi, xi + dx) - xi;  // and within its drift ball
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
