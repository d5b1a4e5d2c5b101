// The self-collision grid's helpers: the order-preserving bits of a float (for atomicMin /
// atomicMax on the box) and the clamped cell of a position. After kernel_head in every grid
// kernel (self_head in src/gpu/self_collision_shaders.cpp).
uint sc_bits(float f) {
  uint b = floatBitsToUint(f);
  return (b & 0x80000000u) != 0u ? ~b : (b | 0x80000000u);
}
float sc_float(uint u) {
  return uintBitsToFloat((u & 0x80000000u) != 0u ? (u & 0x7fffffffu) : ~u);
}
// Positions outside the grid (or not finite) go to its border cells: they only gain candidates,
// which the distance test then rejects.
uint sc_cell_of(vec3 p, SelfGrid g) {
  vec3 q = (p - vec3(g.origin_x, g.origin_y, g.origin_z)) / g.cell;
  if (any(isnan(q))) q = vec3(0.0);
  q = clamp(q, vec3(0.0), vec3(float(g.nx - 1u), float(g.ny - 1u), float(g.nz - 1u)));
  uvec3 c = uvec3(q);
  return (c.z * g.ny + c.y) * g.nx + c.x;
}
