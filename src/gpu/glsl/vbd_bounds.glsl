// The body of vbd_bounds_shader (src/gpu/gpu_vbd_shaders.cpp, which puts the kernel's head,
// buffers and vbd_contacts.glsl before it): each point's bound at the current x, the CPU's
// take_bounds: BOUND_FRACTION of its distance to its nearest pair partner and of its stencils'
// distances beyond their floors (stencil_bound; +inf with none).
void main() {
  uint i = gl_GlobalInvocationID.x;
  if (i >= u_count) return;
  vec3 xi = LOAD3(x, i);
  float b = uintBitsToFloat(0x7f800000u);
  uint end = vc_pair_first(i + 1u);
  for (uint e = vc_pair_first(i); e < end; ++e)
    b = min(b, BOUND_FRACTION * length(xi - LOAD3(x, vbd_contacts[vc_pair(e)])));
  end = vc_stencil_first(i + 1u);
  for (uint r = vc_stencil_first(i); r < end; ++r) {
    uint e = vc_stencil_entry(r) / 4u;
    float radius = vc_float(vc_stencil(e) + 6u);
    b = min(b, stencil_bound(BOUND_FRACTION, vc_stencil_distance(e), radius, STENCIL_FLOOR));
  }
  vbd_contacts[vc_bound_word(i)] = floatBitsToUint(b);
}
