// The body of vbd_bounds_shader (src/gpu/gpu_vbd_shaders.cpp, which puts the kernel's head,
// buffers and vbd_pairs.glsl before it): each point's bound at the current x, the CPU's
// take_bounds over the pairs: BOUND_FRACTION of its distance to its nearest partner (+inf with
// none).
void main() {
  uint i = gl_GlobalInvocationID.x;
  if (i >= u_count) return;
  vec3 xi = LOAD3(x, i);
  float b = uintBitsToFloat(0x7f800000u);
  uint end = vp_first(i + 1u);
  for (uint e = vp_first(i); e < end; ++e)
    b = min(b, BOUND_FRACTION * length(xi - LOAD3(x, vbd_pairs[vp_entry(e)])));
  vbd_pairs[vp_bound_word(i)] = floatBitsToUint(b);
}
