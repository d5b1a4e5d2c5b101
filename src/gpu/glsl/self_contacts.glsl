// The body of self_contacts_shader (src/gpu/self_collision_shaders.cpp, which puts the kernel's
// head, buffers and laws before it).
uniform float u_radius;     // s, m: contact distance and the law's rest length
uniform float u_stiffness;  // N/m
uniform float u_damping;    // N.s/m
uniform float u_friction;   // mu
uniform float u_slip;       // m/s: friction is viscous below
uniform bool u_exclude;     // apply the exclusion rows
bool sc_excluded_pair(uint a, uint b) {
  uint lo = sc_excluded_offset[a], hi = sc_excluded_offset[a + 1u];
  while (lo < hi) {
    uint mid = (lo + hi) >> 1u, m = sc_excluded[mid];
    if (m == b) return true;
    if (m < b) lo = mid + 1u; else hi = mid;
  }
  return false;
}
void main() {
  uint a = gl_GlobalInvocationID.x;
  if (a >= u_count) return;
  SelfGrid g = sc_grid[0];
  uint pa = sc_particle[a];
  vec3 xa = LOAD3(x, pa), va = LOAD3(v, pa);
  uint cell = sc_slot[2u * a];
  ivec3 c = ivec3(int(cell % g.nx), int((cell / g.nx) % g.ny), int(cell / (g.nx * g.ny)));
  ivec3 dims = ivec3(int(g.nx), int(g.ny), int(g.nz));
  float s2 = u_radius * u_radius;
  vec3 fi = vec3(0.0);
  uint found = 0u;
  for (int dz = -1; dz <= 1; ++dz)
    for (int dy = -1; dy <= 1; ++dy)
      for (int dx = -1; dx <= 1; ++dx) {
        ivec3 o = c + ivec3(dx, dy, dz);
        if (any(lessThan(o, ivec3(0))) || any(greaterThanEqual(o, dims))) continue;
        uint other = uint((o.z * dims.y + o.y) * dims.x + o.x);
        uint end = sc_cell_start[other + 1u];
        for (uint e = sc_cell_start[other]; e < end; ++e) {
          uint b = sc_order[e];
          if (b == a) continue;
          uint pb = sc_particle[b];
          vec3 xb = LOAD3(x, pb);
          vec3 d = xb - xa;
          if (dot(d, d) >= s2) continue;
          if (u_exclude && sc_excluded_pair(a, b)) continue;
          vec3 vb = LOAD3(v, pb);
          vec3 fn = contact_normal_law(xa, xb, va, vb, u_stiffness, u_damping, u_radius);
          fi += fn;
          if (u_friction > 0.0)
            fi += contact_friction_law(xa, xb, va, vb, fn, u_friction, u_slip);
          ++found;
        }
      }
  STORE3(f, pa, LOAD3(f, pa) + fi);
  sc_contacts[a] = found;
}
