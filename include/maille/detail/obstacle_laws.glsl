// Geometric contacts' laws ([[obstacle]] method = "geometric" and the [[geometric_contact]]
// bricks): the canonical shapes' distance functions and the contact law with its friction and
// stiffness, written once and compiled twice like link_laws.glsl (its rules hold here).
// include/maille/shared_laws.hpp includes this file in namespace maille::law (`real` = Real):
// src/collision/shapes/shapes.cpp and the geometric obstacle stage call these functions, so the
// CPU's results are theirs bit for bit. The GPU backend's obstacle kernels
// (src/gpu/gpu_obstacle_shaders.cpp) paste the text with `real` = float.
//
// More rules for this file: out parameters are MAILLE_OUT(T) and in-out ones MAILLE_INOUT(T)
// (T& in C++, `out T` / `inout T` in GLSL), written on every path; a matrix product is M * v
// (Mat3's row-major product in C++, GLSL's own there: the GPU uploads the same matrix) and
// transpose(M) * v; largest_real() is the scalar type's largest finite value.
//
// A shape's distance function takes a point p of its canonical frame (and the shape's parameter
// if it has one) and returns the signed distance (negative inside), with the outward unit normal
// of the closest surface point in `normal`; each one's rule for ties is written beside it.
//
// The shapes' numbers (ShapeKind's values): each is the index of its row in the shape table,
// src/collision/shapes/shape_table.cpp, which checks it.
const int kShapeSphere = 0;
const int kShapeCube = 1;
const int kShapeCylinder = 2;
const int kShapeCone = 3;
const int kShapeTorus = 4;
const int kShapeCapsule = 5;
const int kShapePlane = 6;

// Ties: the centre gets +y.
MAILLE_SHARED real sphere_distance(vec3 p, MAILLE_OUT(vec3) normal) {
  real n = sqrt(dot(p, p));
  normal = n > real(0) ? p / n : vec3(real(0), real(1), real(0));
  return n - real(1);
}

// Outside: the Euclidean distance to the box (the max norm's level set 1 is the surface);
// inside: the distance to the nearest face. Ties between faces: y, then x, then z.
MAILLE_SHARED real cube_distance(vec3 p, MAILLE_OUT(vec3) normal) {
  vec3 q = vec3(abs(p.x) - real(1), abs(p.y) - real(1), abs(p.z) - real(1));
  vec3 s = vec3(p.x < real(0) ? real(-1) : real(1), p.y < real(0) ? real(-1) : real(1),
                p.z < real(0) ? real(-1) : real(1));
  vec3 o = vec3(max(q.x, real(0)), max(q.y, real(0)), max(q.z, real(0)));
  real outside = sqrt(dot(o, o));
  if (outside > real(0)) {
    normal = vec3(s.x * o.x, s.y * o.y, s.z * o.z) / outside;
    return outside;
  }
  // Inside or on the surface: the largest of q (closest face), y first on ties.
  if (q.y >= q.x && q.y >= q.z) {
    normal = vec3(real(0), s.y, real(0));
    return q.y;
  }
  if (q.x >= q.z) {
    normal = vec3(s.x, real(0), real(0));
    return q.x;
  }
  normal = vec3(real(0), real(0), s.z);
  return q.z;
}

// Solids of revolution about y (cylinder, cone) are solved in their (r, y) half-plane: the
// radial unit vector of p (+x on the axis), r its distance to the axis.
MAILLE_SHARED vec3 radial_direction(vec3 p, MAILLE_OUT(real) r) {
  r = sqrt(p.x * p.x + p.z * p.z);
  return r > real(0) ? vec3(p.x / r, real(0), p.z / r) : vec3(real(1), real(0), real(0));
}

// One boundary edge (a, b) of the (r, y) outline: kept when its closest point to q is nearer
// than `best` (a squared distance), with that point (r, y, 0) and the edge's b - a (r, y, 0).
// Callers try the edges in order (caps first): ties go to the first.
MAILLE_SHARED void revolve_edge(real qr, real qy, real ar, real ay, real br, real by,
                                MAILLE_INOUT(real) best, MAILLE_INOUT(vec3) closest,
                                MAILLE_INOUT(vec3) edge) {
  real dr = br - ar;
  real dy = by - ay;
  real len2 = dr * dr + dy * dy;
  real t = len2 > real(0) ? ((qr - ar) * dr + (qy - ay) * dy) / len2 : real(0);
  t = clamp(t, real(0), real(1));
  real kr = ar + t * dr;
  real ky = ay + t * dy;
  real d2 = (qr - kr) * (qr - kr) + (qy - ky) * (qy - ky);
  if (d2 < best) {
    best = d2;
    closest = vec3(kr, ky, real(0));
    edge = vec3(dr, dy, real(0));
  }
}

// The signed distance and normal from the closest edge found: the direction to the closest
// point (inward inside), or on the surface the edge's outward normal (edges run
// counter-clockwise), turned back to 3-D along the radial direction.
MAILLE_SHARED real revolve_distance(vec3 p, real best, vec3 closest, vec3 edge, bool inside,
                                    MAILLE_OUT(vec3) normal) {
  real r = real(0);
  vec3 out_r = radial_direction(p, r);
  real d = sqrt(best);
  real nr = real(0);
  real ny = real(0);
  if (d > real(0)) {
    nr = (r - closest.x) / d;
    ny = (p.y - closest.y) / d;
    if (inside) {
      nr = -nr;
      ny = -ny;
    }
  } else {
    real len = sqrt(edge.x * edge.x + edge.y * edge.y);
    nr = edge.y / len;
    ny = -edge.x / len;
  }
  normal = out_r * nr + vec3(real(0), ny, real(0));
  return inside ? -d : d;
}

MAILLE_SHARED real cylinder_distance(vec3 p, MAILLE_OUT(vec3) normal) {
  real r = real(0);
  radial_direction(p, r);
  bool inside = r < real(1) && abs(p.y) < real(1);
  real best = largest_real();
  vec3 closest = zero3();
  vec3 edge = zero3();
  revolve_edge(r, p.y, real(1), real(1), real(0), real(1), best, closest, edge);
  revolve_edge(r, p.y, real(0), real(-1), real(1), real(-1), best, closest, edge);
  revolve_edge(r, p.y, real(1), real(-1), real(1), real(1), best, closest, edge);
  return revolve_distance(p, best, closest, edge, inside, normal);
}

// A frustum: radius 1 at y = -1, `top` at y = 1; a pointed one (top <= 0) has no top cap.
MAILLE_SHARED real cone_distance(vec3 p, real top, MAILLE_OUT(vec3) normal) {
  real r = real(0);
  radial_direction(p, r);
  real radius_at_y = real(1) + (top - real(1)) * (p.y + real(1)) / real(2);
  bool inside = abs(p.y) < real(1) && r < radius_at_y;
  real best = largest_real();
  vec3 closest = zero3();
  vec3 edge = zero3();
  if (top <= real(0)) {
    revolve_edge(r, p.y, real(0), real(-1), real(1), real(-1), best, closest, edge);
    revolve_edge(r, p.y, real(1), real(-1), real(0), real(1), best, closest, edge);
  } else {
    revolve_edge(r, p.y, top, real(1), real(0), real(1), best, closest, edge);
    revolve_edge(r, p.y, real(0), real(-1), real(1), real(-1), best, closest, edge);
    revolve_edge(r, p.y, real(1), real(-1), top, real(1), best, closest, edge);
  }
  return revolve_distance(p, best, closest, edge, inside, normal);
}

// The tube about the unit circle: ties (on the circle itself) get +y; on the axis, +x.
MAILLE_SHARED real torus_distance(vec3 p, real tube, MAILLE_OUT(vec3) normal) {
  real r = real(0);
  vec3 out_r = radial_direction(p, r);
  real qr = r - real(1);
  real qy = p.y;
  real len = sqrt(qr * qr + qy * qy);
  if (len == real(0)) {
    normal = vec3(real(0), real(1), real(0));
    return -tube;
  }
  normal = out_r * (qr / len) + vec3(real(0), qy / len, real(0));
  return len - tube;
}

// The segment's closest point; on the segment itself (the axis inside), +x.
MAILLE_SHARED real capsule_distance(vec3 p, MAILLE_OUT(vec3) normal) {
  vec3 c = vec3(real(0), clamp(p.y, real(-1), real(1)), real(0));
  vec3 d = p - c;
  real n = sqrt(dot(d, d));
  normal = n > real(0) ? d / n : vec3(real(1), real(0), real(0));
  return n - real(1);
}

// The half-space y <= 0.
MAILLE_SHARED real half_space_distance(vec3 p, MAILLE_OUT(vec3) normal) {
  normal = vec3(real(0), real(1), real(0));
  return p.y;
}

// The distance function of a shape (its kShape* value), with its parameter (the shape table's:
// ignored by a shape without one).
MAILLE_SHARED real canonical_distance(int shape, vec3 p, real parameter, MAILLE_OUT(vec3) normal) {
  if (shape == kShapeSphere) return sphere_distance(p, normal);
  if (shape == kShapeCube) return cube_distance(p, normal);
  if (shape == kShapeCylinder) return cylinder_distance(p, normal);
  if (shape == kShapeCone) return cone_distance(p, parameter, normal);
  if (shape == kShapeTorus) return torus_distance(p, parameter, normal);
  if (shape == kShapeCapsule) return capsule_distance(p, normal);
  return half_space_distance(p, normal);
}

// A canonical normal as a unit world normal: M_i^T n, normalised (+y if it vanishes).
MAILLE_SHARED vec3 normal_to_world(mat3 inverse, vec3 n) {
  vec3 w = transpose(inverse) * n;
  real l = sqrt(dot(w, w));
  return l > real(0) ? w / l : vec3(real(0), real(1), real(0));
}

// The geometric contact (the canonical-frame algorithm) with shape `shape` (its parameter:
// `parameter`): x into the canonical frame through M_i
// (`inverse`, `translation`), the shape's penetration vector there, the spring-damper k d -
// z (v_c . n) n on it, back through M_d (`direct`). With `world_normal`, along the world normal
// with the world depth of the canonical penetration. `v` is the velocity relative to the
// shape's surface. Returns the force (zero outside); `depth` the world penetration (0 outside)
// and `normal` the unit world normal (zero outside).
MAILLE_SHARED vec3 geometric_contact_law(int shape, real parameter, mat3 direct, mat3 inverse,
                                         vec3 translation, vec3 x, vec3 v, real k, real z,
                                         bool world_normal, MAILLE_OUT(real) depth,
                                         MAILLE_OUT(vec3) normal) {
  depth = real(0);
  normal = zero3();
  vec3 c = inverse * (x - translation);
  vec3 cn = zero3();
  real sd = canonical_distance(shape, c, parameter, cn);
  if (!(sd < real(0))) return zero3();
  vec3 pen_c = cn * (-sd);
  vec3 n = normal_to_world(inverse, cn);
  // n is unit already; the division keeps the CPU's historical rounding (1e-30 vanishes
  // against |n| = 1 in double as in float).
  normal = n * (real(1) / (sqrt(dot(n, n)) + real(1e-30)));
  if (!world_normal) {
    vec3 vc = inverse * v;
    vec3 pen = direct * pen_c;
    depth = sqrt(dot(pen, pen));
    return direct * (pen_c * k - cn * (z * dot(vc, cn)));
  }
  depth = max(dot(direct * pen_c, n), real(0));
  return n * (k * depth - z * dot(v, n));
}

// A geometric obstacle's contact at (x, vr), vr the velocity relative to the obstacle's surface:
// the law above, then Coulomb friction mu F_n against the sliding velocity, viscous below
// `slip` (m/s). F_n and the normal are the contact's own, or held from the step's start
// (`lagged`: lag_force, lag_normal; implicit solvers' lagged friction). Sets `depth`, `normal`,
// `normal_force` (max(F . n, 0) while in contact, else 0), `stiffness`, the block
// -df/dx - (1/h) df/dv implicit solvers take: (k + z/h) n n^T in contact, plus
// (mu F_n / max(|v_t|, slip)) / h (I - n n^T) for friction (its scale held: IPC's lagged form),
// and `rubbing` (friction acts). Returns the force.
MAILLE_SHARED vec3 obstacle_contact_law(int shape, real parameter, mat3 direct, mat3 inverse,
                                        vec3 translation, vec3 x, vec3 vr, real k, real z,
                                        bool world_normal, real mu, real slip, real inv_h,
                                        bool lagged, real lag_force, vec3 lag_normal,
                                        MAILLE_OUT(real) depth, MAILLE_OUT(vec3) normal,
                                        MAILLE_OUT(real) normal_force, MAILLE_OUT(mat3) stiffness,
                                        MAILLE_OUT(bool) rubbing) {
  normal_force = real(0);
  stiffness = identity3() * real(0);
  rubbing = false;
  vec3 force = geometric_contact_law(shape, parameter, direct, inverse, translation, x, vr, k, z,
                                     world_normal, depth, normal);
  if (depth > real(0)) {
    stiffness = outer3(normal, normal) * (k + z * inv_h);
    normal_force = max(dot(force, normal), real(0));
  }
  if (!(mu > real(0))) return force;
  real fn = lagged ? lag_force : normal_force;
  vec3 n = lagged ? lag_normal : normal;
  if (!(fn > real(0))) return force;
  vec3 vt = vr - n * dot(vr, n);
  real scale = mu * fn / max(sqrt(dot(vt, vt)), slip);
  force -= vt * scale;
  stiffness += (identity3() - outer3(n, n)) * (scale * inv_h);
  rubbing = true;
  return force;
}
