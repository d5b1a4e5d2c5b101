// The body of self_grid_shader (src/gpu/self_collision_shaders.cpp, which puts the kernel's head,
// buffers and laws before it).
uniform float u_cell;   // m: the smallest cell size (>= the contact distance)
uniform uint u_budget;  // cells at most
void main() {
  if (gl_GlobalInvocationID.x != 0u) return;
  SelfGrid g = sc_grid[0];
  vec3 lo = vec3(sc_float(g.lo_x), sc_float(g.lo_y), sc_float(g.lo_z));
  vec3 hi = vec3(sc_float(g.hi_x), sc_float(g.hi_y), sc_float(g.hi_z));
  if (!(lo.x <= hi.x)) lo = hi = vec3(0.0);  // no finite position
  vec3 ext = min(hi - lo, vec3(1.0e30));
  // As the CPU's uniform grid: the cell grows by 1.25 until the box fits the budget.
  float c = u_cell;
  uvec3 n = uvec3(1u);
  for (int k = 0; k < 1000; ++k, c *= 1.25) {
    vec3 q = floor(ext / c) + 1.0;
    if (q.x * q.y * q.z > float(u_budget)) continue;
    n = uvec3(q);
    if (n.x * n.y * n.z <= u_budget) break;  // exact (the float product was within rounding)
  }
  g.origin_x = lo.x;
  g.origin_y = lo.y;
  g.origin_z = lo.z;
  g.cell = c;
  g.nx = n.x;
  g.ny = n.y;
  g.nz = n.z;
  g.lo_x = g.lo_y = g.lo_z = 0xffffffffu;  // the next step's box starts empty
  g.hi_x = g.hi_y = g.hi_z = 0u;
  sc_grid[0] = g;
}
