// The body of self_bounds_shader (src/gpu/self_collision_shaders.cpp, which puts the kernel's head,
// buffers and laws before it).
shared vec3 s_lo[gl_WorkGroupSize.x];
shared vec3 s_hi[gl_WorkGroupSize.x];
void main() {
  uint a = gl_GlobalInvocationID.x, t = gl_LocalInvocationID.x;
  vec3 lo = vec3(3.0e38), hi = vec3(-3.0e38);
  if (a < u_count) {
    vec3 p = LOAD3(x, sc_particle[a]);
    if (!any(isnan(p)) && !any(isinf(p))) lo = hi = p;
  }
  s_lo[t] = lo;
  s_hi[t] = hi;
  for (uint d = gl_WorkGroupSize.x / 2u; d > 0u; d >>= 1u) {
    memoryBarrierShared();
    barrier();
    if (t < d) {
      s_lo[t] = min(s_lo[t], s_lo[t + d]);
      s_hi[t] = max(s_hi[t], s_hi[t + d]);
    }
  }
  if (t == 0u && s_lo[0].x <= s_hi[0].x) {
    atomicMin(sc_grid[0].lo_x, sc_bits(s_lo[0].x));
    atomicMin(sc_grid[0].lo_y, sc_bits(s_lo[0].y));
    atomicMin(sc_grid[0].lo_z, sc_bits(s_lo[0].z));
    atomicMax(sc_grid[0].hi_x, sc_bits(s_hi[0].x));
    atomicMax(sc_grid[0].hi_y, sc_bits(s_hi[0].y));
    atomicMax(sc_grid[0].hi_z, sc_bits(s_hi[0].z));
  }
}
