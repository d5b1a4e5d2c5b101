// The step's point pairs in the GPU's VBD kernels (src/gpu/gpu_vbd_pairs.hpp): vbd_pairs' layout
// (gpu_layout.hpp) and each pair's terms from the shared laws. Pasted after the kernel's head
// and, for pair_terms, after link_laws.glsl; PAIR_WORDS, BOUND_FRACTION and SLIP are defined
// by the C++ (kVbdPairWords, kBoundFraction, kSelfCollisionSlip).
uniform bool u_pairs;  // this step has pairs (else vbd_pairs is not read)
uint vp_points() { return vbd_pairs[0]; }
uint vp_first(uint i) { return vbd_pairs[1u + i]; }
uint vp_bound_word(uint i) { return vp_points() + 2u + i; }
float vp_bound(uint i) { return uintBitsToFloat(vbd_pairs[vp_bound_word(i)]); }
uint vp_entry(uint e) { return 2u * vp_points() + 2u + PAIR_WORDS * e; }
float vp_value(uint w, uint k) { return uintBitsToFloat(vbd_pairs[w + 1u + k]); }

// A move dx of point i shortened to its bound (the CPU's within_bound).
vec3 vp_within_bound(uint i, vec3 dx) {
  if (!u_pairs) return dx;
  float b = vp_bound(i), len2 = dot(dx, dx);
  return len2 > b * b ? dx * (b / sqrt(len2)) : dx;
}

// Whether point i has a bound (a pair): it is not extrapolated.
bool vp_bounded(uint i) {
  return u_pairs && !isinf(vp_bound(i));
}

#ifdef PAIR_TERMS
// Point i's pairs at (xi, vi), their partners at the current x, v: the conditional
// spring-damper's force and block (J_x + J_v / h, definite) and the lagged friction's, added to
// g and H (the CPU's FrictionalContact / ConditionalSpringDamper terms).
void pair_terms(uint i, vec3 xi, vec3 vi, float inv_h, inout vec3 g, inout mat3 H) {
  if (!u_pairs) return;
  uint end = vp_first(i + 1u);
  for (uint e = vp_first(i); e < end; ++e) {
    uint w = vp_entry(e);
    uint j = vbd_pairs[w];
    vec3 xj = LOAD3(x, j), vj = LOAD3(v, j);
    float k = vp_value(w, 0u), z = vp_value(w, 1u), s = vp_value(w, 2u), rest = vp_value(w, 3u);
    g += conditional_law(xi, xj, vi, vj, k, z, s, rest);
    H += conditional_law_block(xi, xj, vi, vj, k, z, s, rest, inv_h);
    vec3 n = vec3(vp_value(w, 6u), vp_value(w, 7u), vp_value(w, 8u));
    float scale = lagged_friction_scale(vi, vj, n, vp_value(w, 4u), vp_value(w, 5u), SLIP);
    if (scale > 0.0) {
      g += lagged_friction_force(vi, vj, n, scale);
      H += lagged_friction_block(n, scale, inv_h);
    }
  }
}
#endif
