vec3 point_at(uint k) { return vec3(xyz[3u * k], xyz[3u * k + 1u], xyz[3u * k + 2u]); }
vec3 normal_at(uint k) {
  return vec3(normal_xyz[3u * k], normal_xyz[3u * k + 1u], normal_xyz[3u * k + 2u]);
}
// Control point (c, d) of a grid, extrapolated linearly beyond its border (as on the CPU).
vec3 fetch(Grid g, int c, int d) { return point_at(g.first + uint(d * int(g.nx) + c)); }
vec3 column(Grid g, int c, int d) {
  int ny = int(g.ny);
  if (d < 0) return fetch(g, c, 0) * 2.0f - fetch(g, c, 1);
  if (d >= ny) return fetch(g, c, ny - 1) * 2.0f - fetch(g, c, ny - 2);
  return fetch(g, c, d);
}
vec3 control(Grid g, int a, int b) {
  int nx = int(g.nx);
  if (a < 0) return column(g, 0, b) * 2.0f - column(g, 1, b);
  if (a >= nx) return column(g, nx - 1, b) * 2.0f - column(g, nx - 2, b);
  return column(g, a, b);
}
void main() {
  uint id = gl_GlobalInvocationID.x;
  if (id >= u_total) return;
  vec3 s, t1, t2;
  float step = 1.0f / float(u_lod);
  uint lod = uint(u_lod);
  if (id < u_grid_vertices) {
    int gi = 0;
    while (gi + 1 < u_grid_count && grids[gi + 1].offset <= id) ++gi;
    Grid g = grids[gi];
    uint local = id - g.offset;
    uint cols = lod * (g.nx - 1u) + 1u;
    uint a = local % cols, b = local / cols;
    uint i = min(a / lod, g.nx - 2u), j = min(b / lod, g.ny - 2u);
    float u = float(a - i * lod) * step, v = float(b - j * lod) * step;
    vec3 p[16];
    for (int r = 0; r < 4; ++r)
      for (int c = 0; c < 4; ++c) p[4 * r + c] = control(g, int(i) - 1 + c, int(j) - 1 + r);
    cr_patch(p, u, v, s, t1, t2);
  } else {
    uint per = uint((u_lod + 1) * (u_lod + 2) / 2);
    uint k = id - u_grid_vertices;
    uint t = k / per;
    int local = int(k % per), j = 0;
    while (local > u_lod - j) { local -= u_lod + 1 - j; ++j; }
    uint a = tri[3u * t], b = tri[3u * t + 1u], c = tri[3u * t + 2u];
    pn_triangle(point_at(a), point_at(b), point_at(c), normal_at(a), normal_at(b), normal_at(c),
                float(local) * step, float(j) * step, s, t1, t2);
  }
  vec3 n = unit_normal(t1, t2);
  vout[6u * id] = s.x; vout[6u * id + 1u] = s.y; vout[6u * id + 2u] = s.z;
  vout[6u * id + 3u] = n.x; vout[6u * id + 4u] = n.y; vout[6u * id + 5u] = n.z;
}
