// Self-collision's contact laws between the primitives of a surface, written once and compiled
// twice like link_laws.glsl (its rules hold here, and obstacle_laws.glsl's for MAILLE_OUT):
// include/maille/shared_laws.hpp includes this file in namespace maille::law (`real` = Real),
// and the GPU backend's shaders paste its text with `real` = float (tests/gpu compares the two).
//
// A contact joins two points, one on each primitive, each a weighted sum of the primitives'
// corners: a *stencil* of four points with coefficients c (sum c_j x_j = d, the gap vector from
// the second primitive to the first):
//   point-triangle  {p, a, b, c}:     c = (1, -w_a, -w_b, -w_c), w the closest point's weights
//   edge-edge       {a0, a1, b0, b1}: c = (1 - s, s, -(1 - t), -t), s and t the closest points'
//                                     parameters on the two segments
// With d = |d| < s (the contact radius, the layer's thickness) the energy is the penalty
// E = k (s - d)^2 / 2, the force on the first side F = n (k (s - d) - z n.dv) (n = d / d, dv =
// sum c_j v_j: a damper along n), and stencil point j takes c_j F. The weights are the closest
// points', so dE/dw = 0 there (the gap is stationary in them): F's elastic part is exactly
// -dE/dx_p on the particle and c_j times it on the others (tests/unit/test_contact_laws.cpp checks
// it by finite differences). The block each solver adds per stencil point is the energy's
// Gauss-Newton Hessian c_j^2 (k + z / h) n n^T: the exact Hessian adds k (s - d) / d times the
// transverse projector's change, negative for a pressed pair, which would cost definiteness.

// triangle_closest_weights' test of a corner X past a (b, then c) and of the edge aX: `own` is
// that edge, `other` the edge aY to the third corner, xa and ya their dot products with p - a;
// xx and yx are set to their dot products with p - X. 1 when p's closest point is X, 2 when it
// lies on aX at parameter t from a, else 0. `area` (Ericson's vc for b, vb for c) is the face
// region's weight of the third corner.
MAILLE_SHARED int corner_or_edge(vec3 own, vec3 other, vec3 xp, real xa, real ya,
                                 MAILLE_OUT(real) xx, MAILLE_OUT(real) yx, MAILLE_OUT(real) area,
                                 MAILLE_OUT(real) t) {
  xx = dot(own, xp);
  yx = dot(other, xp);
  area = real(0);
  t = real(0);
  if (xx >= real(0) && yx <= xx) return 1;
  area = xa * yx - xx * ya;
  if (area <= real(0) && xa >= real(0) && xx <= real(0)) {
    t = xa / (xa - xx);
    return 2;
  }
  return 0;
}

// Closest point of triangle abc to p, as barycentric weights (Ericson, Real-Time Collision
// Detection, 5.1.5): the Voronoi regions of the corners, the edges, then the face. Weights are
// exact zeros outside the touched feature (callers name the feature from them).
MAILLE_SHARED vec3 triangle_closest_weights(vec3 p, vec3 a, vec3 b, vec3 c) {
  vec3 ab = b - a;
  vec3 ac = c - a;
  vec3 ap = p - a;
  real d1 = dot(ab, ap);
  real d2 = dot(ac, ap);
  if (d1 <= real(0) && d2 <= real(0)) return vec3(real(1), real(0), real(0));
  real d3, d4, d5, d6, vb, vc, along;
  int near_b = corner_or_edge(ab, ac, p - b, d1, d2, d3, d4, vc, along);
  if (near_b != 0)
    return near_b == 1 ? vec3(real(0), real(1), real(0)) : vec3(real(1) - along, along, real(0));
  int near_c = corner_or_edge(ac, ab, p - c, d2, d1, d6, d5, vb, along);
  if (near_c != 0)
    return near_c == 1 ? vec3(real(0), real(0), real(1)) : vec3(real(1) - along, real(0), along);
  real va = d3 * d6 - d5 * d4;
  if (va <= real(0) && (d4 - d3) >= real(0) && (d5 - d6) >= real(0)) {
    real t = (d4 - d3) / ((d4 - d3) + (d5 - d6));
    return vec3(real(0), real(1) - t, t);
  }
  real denom = real(1) / (va + vb + vc);
  real v = vb * denom;
  real w = vc * denom;
  return vec3(real(1) - v - w, v, w);
}

// The parameters s on segment a0a1 and t on b0b1 of the segments' closest points (Ericson,
// 5.1.9), both in [0, 1]. Parallel edges (sin^2 of their angle below 1e-6, about 0.06 degree:
// above float's rounding, so the GPU decides as the CPU does) have a whole
// interval of closest points: s = 0 is taken, then t clamped and s again for that t, so that
// one of the two points is a corner, whose distance to the other edge the point-triangle
// contacts already push (edge_edge_acts): overlapping parallel edges never count twice. As two
// edges turn through parallel the distance and its direction stay continuous; only how the
// force is split among the four ends changes. Degenerate segments (a point) take parameter 0.
MAILLE_SHARED void edge_edge_params(vec3 a0, vec3 a1, vec3 b0, vec3 b1, MAILLE_OUT(real) s,
                                    MAILLE_OUT(real) t) {
  vec3 da = a1 - a0;
  vec3 db = b1 - b0;
  vec3 r = a0 - b0;
  real aa = dot(da, da);
  real bb = dot(db, db);
  real f = dot(db, r);
  s = real(0);
  t = real(0);
  if (aa <= real(1e-30) && bb <= real(1e-30)) return;
  if (aa <= real(1e-30)) {
    t = clamp(f / bb, real(0), real(1));
    return;
  }
  real c = dot(da, r);
  if (bb <= real(1e-30)) {
    s = clamp(-c / aa, real(0), real(1));
    return;
  }
  real ab = dot(da, db);
  real denom = aa * bb - ab * ab;  // |da|^2 |db|^2 sin^2
  s = denom > real(1e-6) * aa * bb ? clamp((ab * f - c * bb) / denom, real(0), real(1)) : real(0);
  t = (ab * s + f) / bb;
  if (t < real(0)) {
    t = real(0);
    s = clamp(-c / aa, real(0), real(1));
  } else if (t > real(1)) {
    t = real(1);
    s = clamp((ab - c) / aa, real(0), real(1));
  }
}

// Whether an edge-edge contact at parameters s, t is the edges' own: both closest points inside
// their segments.
MAILLE_SHARED bool edge_edge_interior(real s, real t) {
  return s > real(0) && s < real(1) && t > real(0) && t < real(1);
}

// Whether the edge pair pushes at s, t, given which of its corners a0, a1, b0, b1 are colliding
// particles. At an end, the closest points are a corner and the other edge: a distance the
// point-triangle contacts of that corner already push along when it is a particle (each shared
// edge and corner counts once), and the force passes from one to the other at the same distance
// and direction (continuous). A corner that is no particle (a fixed border) has no such contact:
// the edge pair keeps it.
MAILLE_SHARED bool edge_edge_acts(real s, real t, bool a0, bool a1, bool b0, bool b1) {
  bool by_corner = (s <= real(0) && a0) || (s >= real(1) && a1) || (t <= real(0) && b0) ||
                   (t >= real(1) && b1);
  return !by_corner;
}

// The penalty energy of a contact at distance `dist` with radius s: k (s - d)^2 / 2 while closer.
MAILLE_SHARED real contact_energy(real dist, real k, real s) {
  real gap = s - dist;
  return dist < s ? real(0.5) * k * gap * gap : real(0);
}

// The force on the first side of a stencil contact of gap vector d (from the second side's point
// to the first's) and relative velocity dv: n (k (s - |d|) - z n.dv) while 0 < |d| < s, else 0.
MAILLE_SHARED vec3 stencil_contact_force(vec3 d, vec3 dv, real k, real z, real s) {
  real d2 = dot(d, d);
  if (!(d2 < s * s) || d2 == real(0)) return zero3();
  real dist = sqrt(d2);
  vec3 n = d / dist;
  return n * (k * (s - dist) - z * dot(dv, n));
}

// VBD's Chebyshev acceleration (the CPU's VertexBlockDescent::extrapolate, the GPU's
// vbd_accelerate.glsl): omega after sweep k from the factor rho and the last omega; a point's
// extrapolated place prev2 + omega (x - prev2), x its iterate and prev2 the one two sweeps back;
// and whether it takes the jump: not while touching an obstacle or bounded by a contact (across
// a stiff contact's jump it lands deep inside, or through a face), nor by more than half the
// thinnest contact region (a thin box crossed unseen). The caller also keeps it in its drift ball.
MAILLE_SHARED real chebyshev_omega(int k, real rho, real omega) {
  return k == 1 ? real(1) : k == 2 ? real(2) / (real(2) - rho * rho)
                                   : real(4) / (real(4) - rho * rho * omega);
}
MAILLE_SHARED vec3 chebyshev_place(vec3 x, vec3 prev2, real omega) {
  return (x - prev2) * omega + prev2;
}
MAILLE_SHARED bool chebyshev_takes(bool touching, bool bounded, vec3 jump, real half_thinnest) {
  return !touching && !bounded && dot(jump, jump) <= half_thinnest * half_thinnest;
}

// A point's conservative bound from one of its stencils at distance d (the implicit solvers'
// bounds per update, the explicit schemes' clamp per step): `share` of the distance beyond the
// stencil's floor, `floor_fraction` of its radius s. An update moves each point of the stencil at
// most that far, so it closes the pair by at most 2 share (d - floor) < d - floor: a pair found
// beyond the floor stays beyond it however many updates press it, and one at the floor holds
// its points. Without the floor, a penalty pressed past its strength k s lets the distance fall
// geometrically, update after update, to the rounding of the positions (1e-11 m on the coarse
// wrung strip), where a crossing is decided by rounding (docs/implicit.md).
MAILLE_SHARED real stencil_bound(real share, real d, real s, real floor_fraction) {
  return share * max(d - floor_fraction * s, real(0));
}

// Its block per unit c_j^2: (k + z / h) n n^T while touching (the Gauss-Newton Hessian of the
// penalty with the damper through v = (x - x_n) / h), else 0.
MAILLE_SHARED mat3 stencil_contact_block(vec3 d, real k, real z, real s, real inv_h) {
  real d2 = dot(d, d);
  if (!(d2 < s * s) || d2 == real(0)) return identity3() * real(0);
  vec3 n = d / sqrt(d2);
  return outer3(n, n) * (k + z * inv_h);
}

// The feature of a triangle {t0, t1, t2} that a closest point at weights w lies on (the
// once-per-feature rule: a contact on an edge or a corner shared by several of a particle's
// candidate triangles pushes once, from the lowest of them): kind 2 the face (a = `face`, an
// index the caller names it by), 1 an edge (its corners a < b), 0 a corner (a). Triangles
// sharing an edge or a corner give it the same kind and ids.
MAILLE_SHARED void triangle_feature(vec3 w, uint t0, uint t1, uint t2, uint face,
                                    MAILLE_OUT(uint) kind, MAILLE_OUT(uint) a,
                                    MAILLE_OUT(uint) b) {
  uint used0 = 0u;
  uint used1 = 0u;
  uint count = 0u;
  if (w.x != real(0)) {
    used0 = t0;
    count = 1u;
  }
  if (w.y != real(0)) {
    if (count == 0u) used0 = t1; else used1 = t1;
    count = count + 1u;
  }
  if (w.z != real(0)) {
    if (count == 0u) used0 = t2; else used1 = t2;
    count = count + 1u;
  }
  kind = count == 3u ? 2u : count == 2u ? 1u : 0u;
  a = count == 3u ? face : count == 2u ? min(used0, used1) : used0;
  b = count == 2u ? max(used0, used1) : 0u;
}

// The drift guard's hold (src/integrators/drift_guard.hpp): a move from `from` to `to` kept in
// the ball |y - centre| <= limit, f = from - centre (as the caller rounds it): the point of the
// segment farthest along it inside the ball (the largest s in [0, 1] with from + s (to - from)
// inside: the roots of |f + s d|^2 = limit^2), or the segment's point nearest the centre when
// the segment misses the ball (its start may lie outside).
MAILLE_SHARED vec3 ball_hold(vec3 from, vec3 to, vec3 f, real limit) {
  vec3 d = to - from;
  real a = dot(d, d);
  real b = dot(f, d);
  real c = dot(f, f) - limit * limit;
  if (!(a > real(0))) return from;
  real disc = b * b - a * c;
  real nearest = clamp(-b / a, real(0), real(1));
  if (disc < real(0)) return from + d * nearest;
  real root = sqrt(disc);
  real in_ = (-b - root) / a;
  real out_ = (-b + root) / a;
  if (out_ < real(0) || in_ > real(1)) return from + d * nearest;
  return from + d * min(out_, real(1));
}
