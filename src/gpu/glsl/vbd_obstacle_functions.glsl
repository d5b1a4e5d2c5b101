// The body of vbd_obstacle_functions (src/gpu/gpu_obstacle_shaders.cpp, which puts the kernel's
// head, buffers and laws before it).
uniform uint u_obstacles;  // geometric obstacles (0: none)
uniform uint u_placed;     // their records' first: 0 placed at t, u_obstacles at t + h
uniform float u_thinnest;  // m: the thinnest obstacle (+inf: none, or planes only)
mat3 ob_direct(ObstacleRecord r) {  // row-major in the record, columns here
  return mat3(r.d00, r.d10, r.d20, r.d01, r.d11, r.d21, r.d02, r.d12, r.d22);
}
mat3 ob_inverse(ObstacleRecord r) {
  return mat3(r.i00, r.i10, r.i20, r.i01, r.i11, r.i21, r.i02, r.i12, r.i22);
}
vec3 ob_translation(ObstacleRecord r) { return vec3(r.tx, r.ty, r.tz); }
bool ob_collides(uint i, uint o) { return ((vbd_ob_member[i] >> o) & 1u) != 0u; }
// The velocity relative to the obstacle's surface (its twist) of a point at xp moving at vp.
vec3 ob_relative_velocity(ObstacleRecord r, vec3 xp, vec3 vp) {
  if (r.moves == 0u) return vp;
  vec3 spin = vec3(r.sx, r.sy, r.sz), center = vec3(r.cx, r.cy, r.cz);
  return vp - (vec3(r.lx, r.ly, r.lz) + cross(spin, xp - center));
}
uint ob_lag_at(uint i, uint o) { return 4u * (i * u_obstacles + o); }
// Obstacle o's contact with point i at (xp, vp) (the CPU stage's contact()): the shared law at
// the velocity relative to the surface; friction's F_n and normal held from the step's start
// when `lagged` and the obstacle has friction.
vec3 ob_contact(uint o, uint i, vec3 xp, vec3 vp, float inv_h, bool lagged, out float depth,
                out mat3 K, out bool rubbing) {
  ObstacleRecord r = vbd_obstacles[u_placed + o];
  bool held = lagged && r.friction > 0.0;
  uint l = ob_lag_at(i, o);
  float lag_force = held ? vbd_ob_lag[l] : 0.0;
  vec3 lag_normal = held ? vec3(vbd_ob_lag[l + 1u], vbd_ob_lag[l + 2u], vbd_ob_lag[l + 3u])
                         : vec3(0.0);
  vec3 vr = ob_relative_velocity(r, xp, vp);
  vec3 normal;
  float normal_force;
  return obstacle_contact_law(int(r.shape), r.shape_parameter, ob_direct(r), ob_inverse(r),
                              ob_translation(r), xp, vr, r.stiffness, r.damping,
                              r.world_normal != 0u, r.friction, r.slip, inv_h, held, lag_force,
                              lag_normal, depth, normal, normal_force, K, rubbing);
}
// The lag (PointContacts::lag): at x_n, v_n placed at t (u_placed = 0), each obstacle's normal
// force (0 out of contact) and normal, for the solve.
void ob_lag(uint i, vec3 xp, vec3 vp) {
  for (uint o = 0u; o < u_obstacles; ++o) {
    if (!ob_collides(i, o) || !(vbd_obstacles[o].friction > 0.0)) continue;
    float depth;
    mat3 K;
    bool rubbing;
    ObstacleRecord r = vbd_obstacles[o];
    vec3 vr = ob_relative_velocity(r, xp, vp);
    vec3 normal;
    float normal_force;
    obstacle_contact_law(int(r.shape), r.shape_parameter, ob_direct(r), ob_inverse(r),
                         ob_translation(r), xp, vr, r.stiffness, r.damping, r.world_normal != 0u,
                         r.friction, r.slip, 0.0, false, 0.0, vec3(0.0), depth, normal,
                         normal_force, K, rubbing);
    uint l = ob_lag_at(i, o);
    vbd_ob_lag[l] = depth > 0.0 ? normal_force : 0.0;
    vbd_ob_lag[l + 1u] = normal.x;
    vbd_ob_lag[l + 2u] = normal.y;
    vbd_ob_lag[l + 3u] = normal.z;
  }
}
// The terms (PointContacts::add_terms) of point i at (xp, vp): forces into g, blocks into H;
// whether an obstacle touches it. Beyond an obstacle's cull sphere only a held friction acts.
bool ob_terms(uint i, vec3 xp, vec3 vp, float inv_h, inout vec3 g, inout mat3 H) {
  bool touching = false;
  for (uint o = 0u; o < u_obstacles; ++o) {
    if (!ob_collides(i, o)) continue;
    ObstacleRecord r = vbd_obstacles[u_placed + o];
    vec3 rel = xp - ob_translation(r);
    bool holds = r.friction > 0.0 && vbd_ob_lag[ob_lag_at(i, o)] > 0.0;
    if (dot(rel, rel) > r.reach2 && !holds) continue;
    float depth;
    mat3 K;
    bool rubbing;
    vec3 f = ob_contact(o, i, xp, vp, inv_h, true, depth, K, rubbing);
    if (depth <= 0.0 && !rubbing) continue;
    g += f;
    H += K;
    if (depth > 0.0) touching = true;
  }
  return touching;
}
// Whether an obstacle touches point i at (xp, vp) (its terms thrown away but g: `g` gets them).
bool ob_touches(uint i, vec3 xp, vec3 vp, float inv_h, out vec3 g) {
  g = vec3(0.0);
  mat3 H = mat3(0.0);
  return ob_terms(i, xp, vp, inv_h, g, H);
}
// Obstacle o's elastic push on point i at xp, at rest relative to its surface (PointContacts::
// push): zero out of contact.
vec3 ob_push(uint o, uint i, vec3 xp) {
  float depth;
  mat3 K;
  bool rubbing;
  ObstacleRecord r = vbd_obstacles[u_placed + o];
  vec3 normal;
  float normal_force;
  vec3 f = obstacle_contact_law(int(r.shape), r.shape_parameter, ob_direct(r), ob_inverse(r),
                                ob_translation(r), xp, vec3(0.0), r.stiffness, r.damping,
                                r.world_normal != 0u, r.friction, r.slip, 0.0, false, 0.0,
                                vec3(0.0), depth, normal, normal_force, K, rubbing);
  return depth > 0.0 ? f : vec3(0.0);
}
// The CPU's leaves_cleanly: a touching point's step from `from` to `to` leaves its contacts
// whole when it moves against no push and stays within half the thinnest obstacle of x_n.
bool ob_leaves_cleanly(uint i, vec3 from, vec3 to, vec3 xn) {
  vec3 dx = to - from;
  for (uint o = 0u; o < u_obstacles; ++o)
    if (ob_collides(i, o) && dot(ob_push(o, i, from), dx) < 0.0) return false;
  float half_ = 0.5 * u_thinnest;
  vec3 d = to - xn;
  return dot(d, d) <= half_ * half_;
}
// The CPU's contact_change: where on x0 -> x0 + dx the point's touching state (`touching` at
// x0) changes, within 2^-OB_BISECTIONS: lo on x0's side, hi beyond.
vec2 ob_contact_change(uint i, vec3 x0, vec3 dx, vec3 xn, float inv_h, bool touching) {
  float lo = 0.0, hi = 1.0;
  for (int k = 0; k < OB_BISECTIONS; ++k) {
    float mid = 0.5 * (lo + hi);
    vec3 tx = x0 + dx * mid;
    vec3 g;
    if (ob_touches(i, tx, (tx - xn) * inv_h, inv_h, g) == touching) lo = mid; else hi = mid;
  }
  return vec2(lo, hi);
}
// The CPU's first_touch: the fraction of x_n -> to at which point i first enters an obstacle
// (touches it after a sample outside, or while moving against its push), just inside; 1 when
// it enters none on the way or, with through_only, touches at `to`. Sampled at half the
// thinnest obstacle, then bisected.
float ob_first_touch(uint i, vec3 from, vec3 to, float inv_h, bool through_only) {
  vec3 d = to - from;
  vec3 g;
  if (through_only && ob_touches(i, to, d * inv_h, inv_h, g)) return 1.0;
  bool before = ob_touches(i, from, vec3(0.0), inv_h, g);
  if (before && dot(g, d) < 0.0) return 0.0;
  float len = length(d);
  int samples = int(min(float(OB_MAX_SAMPLES), ceil(2.0 * len / u_thinnest)));
  for (int k = 1; k <= samples; ++k) {
    float t = float(k) / float(samples);
    bool from_outside = !before;
    before = ob_touches(i, from + d * t, d * (t * inv_h), inv_h, g);
    if (!before || !(from_outside || dot(g, d) < 0.0)) continue;
    float lo = float(k - 1) / float(samples), hi = t;
    for (int b = 0; b < OB_BISECTIONS; ++b) {
      float mid = 0.5 * (lo + hi);
      bool in_ = ob_touches(i, from + d * mid, d * (mid * inv_h), inv_h, g);
      if (!from_outside) in_ = in_ && dot(g, d) < 0.0;
      if (in_) hi = mid; else lo = mid;
    }
    return hi;
  }
  return 1.0;
}
