// The body of self_scan_shader (src/gpu/self_collision_shaders.cpp, which puts the kernel's head,
// buffers and laws before it).
uniform uint u_in;        // where this level's counts start in sc_cell_start (u_count of them)
uniform uint u_sums;      // where their blocks' totals go
uniform bool u_has_sums;  // false on the top level (a single block)
shared uint s_tmp[kBlock];
void main() {
  uint t = gl_LocalInvocationID.x, base = gl_WorkGroupID.x * kBlock;
  uint i0 = base + t, i1 = base + t + kBlock / 2u;
  s_tmp[t] = i0 < u_count ? sc_cell_start[u_in + i0] : 0u;
  s_tmp[t + kBlock / 2u] = i1 < u_count ? sc_cell_start[u_in + i1] : 0u;
  uint step = 1u;
  for (uint d = kBlock / 2u; d > 0u; d >>= 1u, step <<= 1u) {
    memoryBarrierShared();
    barrier();
    if (t < d) s_tmp[step * (2u * t + 2u) - 1u] += s_tmp[step * (2u * t + 1u) - 1u];
  }
  memoryBarrierShared();
  barrier();
  if (t == 0u) {
    if (u_has_sums) sc_cell_start[u_sums + gl_WorkGroupID.x] = s_tmp[kBlock - 1u];
    s_tmp[kBlock - 1u] = 0u;
  }
  for (uint d = 1u; d < kBlock; d <<= 1u) {
    step >>= 1u;
    memoryBarrierShared();
    barrier();
    if (t < d) {
      uint ai = step * (2u * t + 1u) - 1u, bi = step * (2u * t + 2u) - 1u;
      uint left = s_tmp[ai];
      s_tmp[ai] = s_tmp[bi];
      s_tmp[bi] += left;
    }
  }
  memoryBarrierShared();
  barrier();
  if (i0 < u_count) sc_cell_start[u_in + i0] = s_tmp[t];
  if (i1 < u_count) sc_cell_start[u_in + i1] = s_tmp[t + kBlock / 2u];
}
