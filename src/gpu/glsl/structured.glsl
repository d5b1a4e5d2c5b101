// The body of structured_shader (src/gpu/gpu_structured.cpp, which puts the kernel's head, buffers
// and laws before it).
uniform uint u_first;          // the grid's first point: point (i, j) is first + j nx + i
uniform uint u_nx;             // points per row
uniform uint u_local;          // the grid's first point in the grid buffers
uniform uint u_family_set[6];  // each family's parameter set, or 0xffffffff: per link
uniform vec3 u_gravity;        // m/s^2
uniform float u_drag;          // 1/s
uniform bool u_wind;           // face forces to sum
uniform bool u_others;         // some grid point has links off the stencil
vec4 params_of(uint s) {
  return LOAD_PARAMS(s);
}
// The parameter set of the family-f link whose first end is grid point k.
uint family_set(uint f, uint k) {
  uint s = u_family_set[f];
  return s != 0xffffffffu ? s : grid_link_set[6u * k + f];
}
// Point i (grid point k) and its stencil link of family f at index offset o (di + dj nx), as
// the link's first end or its second: the law's force on the first end, its opposite on the
// second (one call of the law, its ends selected: one copy of it in the kernel's loop).
vec3 stencil_link(uint f, uint o, bool second, uint i, uint k, vec3 xi, vec3 vi) {
  uint j = second ? i - o : i + o;
  vec3 xj = LOAD3(x, j);
  vec3 vj = LOAD3(v, j);
  vec4 p = params_of(family_set(f, second ? k - o : k));
  vec3 fa = stencil_force(second ? xj : xi, second ? xi : xj, second ? vj : vi, second ? vi : vj,
                          p);
  return second ? -fa : fa;
}
@TABLES@
// A link off the stencil, as the general kernel runs it.
vec3 other_link(uint e, vec3 xi, vec3 vi) {
  Adjacent l = grid_other[e];
  vec3 xj = LOAD3(x, l.other);
  vec3 vj = LOAD3(v, l.other);
  vec4 p = params_of(l.params);
  if ((l.kind & 0x80000000u) != 0u) return -link_force(l.kind & 0x7fffffffu, xj, xi, vj, vi, p);
  return link_force(l.kind, xi, xj, vi, vj, p);
}
void main() {
  if (gl_GlobalInvocationID.x >= u_count) return;
  uint i = u_first + gl_GlobalInvocationID.x;
  uint k = u_local + gl_GlobalInvocationID.x;
  vec3 xi = LOAD3(x, i);
  vec3 vi = LOAD3(v, i);
  vec3 fi = vec3(0.0);
  uint links = grid_point[k];
  uint e = 0u, end = 0u;  // a plain flag reads no offsets
  if (u_others) e = grid_other_offset[k], end = grid_other_offset[k + 1u];
  uint before = e + (links >> 12);
  for (; e < before; ++e) fi += other_link(e, xi, vi);
  @OFFSETS@
  for (uint n = 0u; n < 12u; ++n) {
    uint bit = kOrder[n];
    if ((links & (1u << bit)) == 0u) continue;
    bool second = bit >= 6u;
    uint f = second ? bit - 6u : bit;
    fi += stencil_link(f, offset[f], second, i, k, xi, vi);
  }  for (; e < end; ++e) fi += other_link(e, xi, vi);
  if (u_wind) {
    uint face_end = face_offset[i + 1u];
    for (uint q = face_offset[i]; q < face_end; ++q) fi += LOAD3(face_force, face_of_point[q]);
  }
  if (inv_mass[i] > 0.0) fi += (u_gravity - vi * u_drag) * mass[i];
  STORE3(f, i, fi);
}
