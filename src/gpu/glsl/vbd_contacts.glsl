// The step's contacts in the GPU's VBD kernels (src/gpu/gpu_vbd_contacts.hpp): vbd_contacts'
// layout (gpu_layout.hpp) and each contact's terms from the shared laws. Pasted after the
// kernel's head; CONTACT_GEOMETRY (the stencils' distances, the drift guard's hold) wants
// contact_laws.glsl pasted before, CONTACT_TERMS (the terms) link_laws.glsl and contact_laws.glsl.
// PAIR_WORDS, STENCIL_WORDS, BOUND_FRACTION and SLIP are defined by the C++ (kVbdPairWords,
// kVbdStencilWords, kBoundFraction, kSelfCollisionSlip).
uniform bool u_contacts;  // this step has pairs or stencils (else vbd_contacts is not read)
uniform bool u_guarded;   // this step's stencils keep a drift limit per point
uint vc_points() { return vbd_contacts[0]; }
float vc_float(uint w) { return uintBitsToFloat(vbd_contacts[w]); }
uint vc_bound_word(uint i) { return vbd_contacts[1] + i; }
float vc_bound(uint i) { return vc_float(vc_bound_word(i)); }
uint vc_pair_first(uint i) { return vbd_contacts[vbd_contacts[2] + i]; }
uint vc_pair(uint e) { return vbd_contacts[3] + PAIR_WORDS * e; }
uint vc_stencil_first(uint i) { return vbd_contacts[vbd_contacts[4] + i]; }
uint vc_stencil_entry(uint k) { return vbd_contacts[vbd_contacts[5] + k]; }
uint vc_stencil(uint e) { return vbd_contacts[6] + STENCIL_WORDS * e; }
uint vc_guard(uint i) { return vbd_contacts[7] + 4u * i; }

// A move dx of point i shortened to its bound (the CPU's within_bound).
vec3 vc_within_bound(uint i, vec3 dx) {
  if (!u_contacts) return dx;
  float b = vc_bound(i), len2 = dot(dx, dx);
  return len2 > b * b ? dx * (b / sqrt(len2)) : dx;
}

// Whether point i has a bound (a pair or a stencil): it is not extrapolated.
bool vc_bounded(uint i) {
  return u_contacts && !isinf(vc_bound(i));
}

// Whether `at` lies within point i's drift ball (its limit about its prediction), or i is not
// guarded.
bool vc_inside(uint i, vec3 at) {
  if (!u_guarded) return true;
  uint w = vc_guard(i);
  float limit = vc_float(w);
  if (isinf(limit)) return true;
  vec3 d = at - vec3(vc_float(w + 1u), vc_float(w + 2u), vc_float(w + 3u));
  return dot(d, d) <= limit * limit;
}

#ifdef CONTACT_GEOMETRY
// A move of point i from `from` to `to` held within its drift ball (the CPU's DriftGuard::hold,
// by the shared ball_hold; the device does not search again inside the step, so a held point
// stays held until the next step's search).
vec3 vc_hold(uint i, vec3 from, vec3 to) {
  if (vc_inside(i, to)) return to;
  uint w = vc_guard(i);
  vec3 centre = vec3(vc_float(w + 1u), vc_float(w + 2u), vc_float(w + 3u));
  return ball_hold(from, to, from - centre, vc_float(w));
}

// Stencil e's corners and its gap at x: the coefficients c (sum c_j x_j = d) and whether it
// is an edge pair (TriangleContactTerms::evaluate and distance).
vec3 vc_stencil_gap(uint e, out uvec4 p, out vec4 c, out bool edge) {
  uint w = vc_stencil(e);
  p = uvec4(vbd_contacts[w], vbd_contacts[w + 1u], vbd_contacts[w + 2u], vbd_contacts[w + 3u]);
  vec3 x0 = LOAD3(x, p.x), x1 = LOAD3(x, p.y), x2 = LOAD3(x, p.z), x3 = LOAD3(x, p.w);
  edge = (vbd_contacts[w + 4u] & 1u) != 0u;
  if (edge) {
    float s, t;
    edge_edge_params(x0, x1, x2, x3, s, t);
    c = vec4(1.0 - s, s, -(1.0 - t), -t);
    return x0 * c.x + x1 * c.y + x2 * c.z + x3 * c.w;
  }
  vec3 wt = triangle_closest_weights(x0, x1, x2, x3);
  c = vec4(1.0, -wt.x, -wt.y, -wt.z);
  return x0 - (x1 * wt.x + x2 * wt.y + x3 * wt.z);
}

// Stencil e's distance at x (TriangleContacts::distance), for the bounds.
float vc_stencil_distance(uint e) {
  uvec4 p;
  vec4 c;
  bool edge;
  return length(vc_stencil_gap(e, p, c, edge));
}
#endif

#ifdef CONTACT_TERMS
// Point i's pairs at (xi, vi), their partners at the current x, v: the conditional
// spring-damper's force and block (J_x + J_v / h, definite) and the lagged friction's, added to
// g and H (the CPU's FrictionalContact / ConditionalSpringDamper terms).
void pair_terms(uint i, vec3 xi, vec3 vi, float inv_h, inout vec3 g, inout mat3 H) {
  if (!u_contacts) return;
  uint end = vc_pair_first(i + 1u);
  for (uint e = vc_pair_first(i); e < end; ++e) {
    uint w = vc_pair(e);
    uint j = vbd_contacts[w];
    vec3 xj = LOAD3(x, j), vj = LOAD3(v, j);
    float k = vc_float(w + 1u), z = vc_float(w + 2u), s = vc_float(w + 3u);
    float rest = vc_float(w + 4u);
    g += conditional_law(xi, xj, vi, vj, k, z, s, rest);
    H += conditional_law_block(xi, xj, vi, vj, k, z, s, rest, inv_h);
    vec3 n = vec3(vc_float(w + 7u), vc_float(w + 8u), vc_float(w + 9u));
    float scale = lagged_friction_scale(vi, vj, n, vc_float(w + 5u), vc_float(w + 6u), SLIP);
    if (scale > 0.0) {
      g += lagged_friction_force(vi, vj, n, scale);
      H += lagged_friction_block(n, scale, inv_h);
    }
  }
}

// The feature a point-triangle stencil touches at weights -c.yzw (triangle_feature).
void vc_feature(uint e, uvec4 p, vec4 c, out uint kind, out uint a, out uint b) {
  triangle_feature(-c.yzw, p.y, p.z, p.w, e, kind, a, b);
}

bool vc_has_corner(uvec4 p, uint q) {
  return p.y == q || p.z == q || p.w == q;
}

// Stencil e at x, v (TriangleContactTerms::evaluate and finish): false when it neither touches
// (closer than its radius, and, for a point-triangle one on an edge or a corner, no earlier
// candidate of its particle touching the same feature) nor rubs (lagged friction); else its
// coefficients c, normal n (touching), force on the particle and friction scale.
bool vc_stencil_eval(uint e, out vec4 c, out vec3 n, out vec3 force, out bool touching,
                     out float friction) {
  uvec4 p;
  bool edge;
  vec3 d = vc_stencil_gap(e, p, c, edge);
  uint w = vc_stencil(e);
  uint flags = vbd_contacts[w + 4u];
  float radius = vc_float(w + 6u), k = vc_float(w + 7u), z = vc_float(w + 8u);
  float mu = vc_float(w + 9u), lag = vc_float(w + 10u);
  bool rubbing = mu > 0.0 && lag > 0.0;
  float d2 = dot(d, d);
  touching = d2 < radius * radius && d2 != 0.0;
  if (edge) {
    touching = touching && edge_edge_acts(c.y, -c.w, (flags & 2u) != 0u, (flags & 4u) != 0u,
                                          (flags & 8u) != 0u, (flags & 16u) != 0u);
  } else if (touching) {
    uint kind, a, b;
    vc_feature(e, p, c, kind, a, b);
    if (kind < 2u)
      for (uint o = e; o-- > vbd_contacts[w + 5u];) {
        uvec4 po;
        vec4 co;
        bool edge_o;
        uint wo = vc_stencil(o);
        po = uvec4(vbd_contacts[wo], vbd_contacts[wo + 1u], vbd_contacts[wo + 2u],
                   vbd_contacts[wo + 3u]);
        if (!vc_has_corner(po, a) || (kind == 1u && !vc_has_corner(po, b))) continue;
        vc_stencil_gap(o, po, co, edge_o);
        uint ko, ao, bo;
        vc_feature(o, po, co, ko, ao, bo);
        if (ko == kind && ao == a && bo == b) {
          touching = false;
          break;
        }
      }
  }
  n = vec3(0.0);
  force = vec3(0.0);
  friction = 0.0;
  if (!touching && !rubbing) return false;
  vec3 dv = LOAD3(v, p.x) * c.x + LOAD3(v, p.y) * c.y + LOAD3(v, p.z) * c.z + LOAD3(v, p.w) * c.w;
  if (touching) {
    n = d / sqrt(d2);
    force = stencil_contact_force(d, dv, k, z, radius);
  }
  if (rubbing) {
    vec3 ln = vec3(vc_float(w + 11u), vc_float(w + 12u), vc_float(w + 13u));
    friction = lagged_friction_scale(vec3(0.0), dv, ln, mu, lag, SLIP);
    force -= lagged_friction_force(vec3(0.0), dv, ln, friction);
  }
  return true;
}

// Point i's stencil terms (TriangleContactTerms::add_point_terms): each candidate it is in,
// in role j, gives c_j F to g and c_j^2 (k + z / h) n n^T (touching) plus the friction's
// c_j^2 scale (I - n n^T) / h (rubbing) to H.
void stencil_terms(uint i, float inv_h, inout vec3 g, inout mat3 H) {
  if (!u_contacts) return;
  uint end = vc_stencil_first(i + 1u);
  for (uint r = vc_stencil_first(i); r < end; ++r) {
    uint entry = vc_stencil_entry(r), e = entry / 4u, role = entry % 4u;
    vec4 c;
    vec3 n, force;
    bool touching;
    float friction;
    if (!vc_stencil_eval(e, c, n, force, touching, friction)) continue;
    float cj = c[role];
    uint w = vc_stencil(e);
    float k = vc_float(w + 7u) + vc_float(w + 8u) * inv_h;
    g += force * cj;
    if (touching) H += outerProduct(n, n) * (k * cj * cj);
    if (friction > 0.0) {
      vec3 ln = vec3(vc_float(w + 11u), vc_float(w + 12u), vc_float(w + 13u));
      H += (mat3(1.0) - outerProduct(ln, ln)) * (friction * inv_h * cj * cj);
    }
  }
}
#endif
