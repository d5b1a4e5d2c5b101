#version 450 core
// bounds of the finite positions: one work group, a strided loop then a tree in shared memory.
// Written as (lo.xyz, any, hi.xyz, 0): any = 0 when no position is finite. For framing a
// device's positions without reading them back; one work group is plenty for a bound read
// once a frame.
layout(local_size_x = 256) in;
layout(std430, binding = 0) readonly buffer Positions { float pos[]; };
layout(std430, binding = 1) writeonly buffer Box { vec4 box[2]; };
uniform uint u_points;
shared vec3 s_lo[256];
shared vec3 s_hi[256];
shared uint s_count[256];
void main() {
  uint t = gl_LocalInvocationID.x;
  vec3 lo = vec3(3.0e38), hi = vec3(-3.0e38);
  uint count = 0u;
  for (uint i = t; i < u_points; i += 256u) {
    vec3 p = vec3(pos[3 * i], pos[3 * i + 1], pos[3 * i + 2]);
    if (any(isnan(p)) || any(isinf(p))) continue;
    lo = min(lo, p);
    hi = max(hi, p);
    ++count;
  }
  s_lo[t] = lo;
  s_hi[t] = hi;
  s_count[t] = count;
  barrier();
  for (uint half_size = 128u; half_size > 0u; half_size >>= 1) {
    if (t < half_size) {
      s_lo[t] = min(s_lo[t], s_lo[t + half_size]);
      s_hi[t] = max(s_hi[t], s_hi[t + half_size]);
      s_count[t] += s_count[t + half_size];
    }
    barrier();
  }
  if (t == 0u) {
    box[0] = vec4(s_lo[0], s_count[0] > 0u ? 1.0 : 0.0);
    box[1] = vec4(s_hi[0], 0.0);
  }
}
