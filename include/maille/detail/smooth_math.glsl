// Smooth surfaces over the physical mesh: the math, written once and compiled
// twice. This file is valid C++ and valid GLSL 4.50: src/surface/smooth_surface.cpp includes it
// after defining a float `vec3` with GLSL's operators and functions, and the renderer's compute
// shader (src/render/shaders.hpp) pastes its text after `#define MAILLE_SHARED` and
// `#define MAILLE_OUT(T) out T`. So the CPU evaluation is the GPU's test oracle and the
// formulas are never copied (the habit of Jolt's shader headers).
//
// Rules for this file: float arithmetic with `f` literals, no `inline`/`const&`/templates, no
// GLSL-only types (vec4, uint vectors), arrays passed as `vec3 p[16]`.

// Catmull-Rom spline through p1 (t = 0) and p2 (t = 1), with p0 and p3 the neighbours:
//   P(t) = 1/2 [2 p1 + (p2 - p0) t + (2 p0 - 5 p1 + 4 p2 - p3) t^2 + (3 p1 - p0 - 3 p2 + p3) t^3]
// It interpolates its control points and its tangent at p1 is (p2 - p0) / 2: C1 across
// segments.
MAILLE_SHARED vec3 cr_point(vec3 p0, vec3 p1, vec3 p2, vec3 p3, float t) {
  float t2 = t * t;
  float t3 = t2 * t;
  float w0 = 0.5f * (-t3 + 2.0f * t2 - t);
  float w1 = 0.5f * (3.0f * t3 - 5.0f * t2 + 2.0f);
  float w2 = 0.5f * (-3.0f * t3 + 4.0f * t2 + t);
  float w3 = 0.5f * (t3 - t2);
  return p0 * w0 + p1 * w1 + p2 * w2 + p3 * w3;
}

// dP/dt of the same segment.
MAILLE_SHARED vec3 cr_tangent(vec3 p0, vec3 p1, vec3 p2, vec3 p3, float t) {
  float t2 = t * t;
  float w0 = 0.5f * (-3.0f * t2 + 4.0f * t - 1.0f);
  float w1 = 0.5f * (9.0f * t2 - 10.0f * t);
  float w2 = 0.5f * (-9.0f * t2 + 8.0f * t + 1.0f);
  float w3 = 0.5f * (3.0f * t2 - 2.0f * t);
  return p0 * w0 + p1 * w1 + p2 * w2 + p3 * w3;
}

// The bicubic Catmull-Rom patch over the grid cell whose corners are p[5], p[6], p[9], p[10]
// (p row-major, 4 x 4: p[4 r + c], c along u, r along v), at (u, v) in [0, 1]^2: the point s and
// its partial derivatives su = dS/du, sv = dS/dv (the normal is their cross product).
MAILLE_SHARED void cr_patch(vec3 p[16], float u, float v, MAILLE_OUT(vec3) s, MAILLE_OUT(vec3) su,
                            MAILLE_OUT(vec3) sv) {
  vec3 r0 = cr_point(p[0], p[1], p[2], p[3], u);
  vec3 r1 = cr_point(p[4], p[5], p[6], p[7], u);
  vec3 r2 = cr_point(p[8], p[9], p[10], p[11], u);
  vec3 r3 = cr_point(p[12], p[13], p[14], p[15], u);
  vec3 d0 = cr_tangent(p[0], p[1], p[2], p[3], u);
  vec3 d1 = cr_tangent(p[4], p[5], p[6], p[7], u);
  vec3 d2 = cr_tangent(p[8], p[9], p[10], p[11], u);
  vec3 d3 = cr_tangent(p[12], p[13], p[14], p[15], u);
  s = cr_point(r0, r1, r2, r3, v);
  su = cr_point(d0, d1, d2, d3, v);
  sv = cr_tangent(r0, r1, r2, r3, v);
}

// A curved PN triangle (Vlachos, Peters, Boyd and Mitchell 2001): the cubic Bezier triangle
// through the corners p1, p2, p3 whose edge control points are the edge thirds projected on
// each corner's tangent plane (normals n1, n2, n3), at barycentric weights (1 - b - c, b, c).
// Writes the point s and its derivatives sb = dS/db, sc = dS/dc (a = 1 - b - c); for a
// counter-clockwise triangle cross(sb, sc) points to the side its flat normal does.
MAILLE_SHARED void pn_triangle(vec3 p1, vec3 p2, vec3 p3, vec3 n1, vec3 n2, vec3 n3, float b,
                               float c, MAILLE_OUT(vec3) s, MAILLE_OUT(vec3) sb,
                               MAILLE_OUT(vec3) sc) {
  float third = 1.0f / 3.0f;
  vec3 b210 = (p1 * 2.0f + p2 - n1 * dot(p2 - p1, n1)) * third;
  vec3 b120 = (p2 * 2.0f + p1 - n2 * dot(p1 - p2, n2)) * third;
  vec3 b021 = (p2 * 2.0f + p3 - n2 * dot(p3 - p2, n2)) * third;
  vec3 b012 = (p3 * 2.0f + p2 - n3 * dot(p2 - p3, n3)) * third;
  vec3 b102 = (p3 * 2.0f + p1 - n3 * dot(p1 - p3, n3)) * third;
  vec3 b201 = (p1 * 2.0f + p3 - n1 * dot(p3 - p1, n1)) * third;
  vec3 e = (b210 + b120 + b021 + b012 + b102 + b201) * (1.0f / 6.0f);
  vec3 m = (p1 + p2 + p3) * third;
  vec3 b111 = e + (e - m) * 0.5f;
  float a = 1.0f - b - c;
  s = p1 * (a * a * a) + p2 * (b * b * b) + p3 * (c * c * c) + b210 * (3.0f * a * a * b) +
      b120 * (3.0f * a * b * b) + b201 * (3.0f * a * a * c) + b021 * (3.0f * b * b * c) +
      b102 * (3.0f * a * c * c) + b012 * (3.0f * b * c * c) + b111 * (6.0f * a * b * c);
  vec3 da = p1 * (3.0f * a * a) + b210 * (6.0f * a * b) + b201 * (6.0f * a * c) +
            b120 * (3.0f * b * b) + b102 * (3.0f * c * c) + b111 * (6.0f * b * c);
  vec3 db = p2 * (3.0f * b * b) + b210 * (3.0f * a * a) + b120 * (6.0f * a * b) +
            b021 * (6.0f * b * c) + b012 * (3.0f * c * c) + b111 * (6.0f * a * c);
  vec3 dc = p3 * (3.0f * c * c) + b201 * (3.0f * a * a) + b102 * (6.0f * a * c) +
            b021 * (3.0f * b * b) + b012 * (6.0f * b * c) + b111 * (6.0f * a * b);
  sb = db - da;
  sc = dc - da;
}

// The unit normal from two tangents (zero where they are parallel: a degenerate spot).
MAILLE_SHARED vec3 unit_normal(vec3 t1, vec3 t2) {
  vec3 n = cross(t1, t2);
  float l = length(n);
  return l > 0.0f ? n * (1.0f / l) : n;
}
