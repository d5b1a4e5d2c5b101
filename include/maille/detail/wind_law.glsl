// The wind's pressure law and its gust sines, written once and compiled twice, like
// link_laws.glsl (same rules; float only, so `f` literals are fine here). The CPU wind stage
// (src/core/gust.hpp, field_forces.cpp) calls these functions in its vectorised loops; the GPU
// backend's face shader pastes this text. The physics is documented in include/maille/fields.hpp
// (WindField) and src/core/gust.hpp.

// sin(2 pi r) for r in [-1/2, 1/2] turn, to float rounding: two folds as compare-selects bring
// 2 pi r into [-pi/2, pi/2], then an odd polynomial of degree 9 fitted to sin(2 pi r) on
// [-1/4, 1/4] (near-minimax: error 3.3e-9), evaluated by Estrin's scheme (short chains the
// processor overlaps instead of Horner's long one). Branch-free so that loops vectorise.
MAILLE_SHARED float sin_half_turn(float r) {
  float folded_high = 0.5f - r;
  r = folded_high < r ? folded_high : r;
  float folded_low = -0.5f - r;
  r = folded_low > r ? folded_low : r;
  // Near (2 pi)^(2n+1) / (2n+1)! with alternating signs, fitted (weighted least squares).
  float z = r * r;
  float z2 = z * z;
  return r * (((6.283185160f + -41.34165504f * z) + z2 * (81.60100468f + -76.54979454f * z)) +
              (z2 * z2) * 39.53678991f);
}

// The gust's four travelling sines: sine k's argument (turns) at a point is its phase at time t
// plus MAILLE_GUST_WAVEk(s, q), with s and q the point's coordinates along and across the wind in
// wavelengths (src/core/gust.hpp: Basis). Macros, so that the host evaluates them in double (the
// phases grow with time) and the GPU in float.
#define MAILLE_GUST_WAVE0(s, q) (-(s))
#define MAILLE_GUST_WAVE1(s, q) (0.5 * (q) - 1.31 * (s))
#define MAILLE_GUST_WAVE2(s, q) (0.3 * (q) - 0.8 * (s))
#define MAILLE_GUST_WAVE3(s, q) (-1.2 * (s))

// The gust's sum of its four sines (s0..s3 = sin of the four reduced arguments), as a factor of
// each of its three amplitude vectors: w - U = along g + across1 s2 + across2 s3.
MAILLE_SHARED float gust_along_factor(float s0, float s1) {
  return 0.6f * s0 + 0.4f * s1;
}

// The wind's force on each corner of a face is a2 times this factor, from d = (w - vc) . a2 and
// l2 = |a2|^2 (a2 the doubled area vector, vc the corners' mean velocity, w the air velocity):
//   F = 1/2 rho C_d A |v_rel . n| (v_rel . n) n / 3 = coef |d| d / |a2|^2 a2,  coef = rho C_d / 12.
// A degenerate face (l2 = 0) gets no force: the division is by l2 + (l2 == 0), so that loops
// vectorise without masks.
MAILLE_SHARED float wind_pressure_scale(float coef, float d, float l2) {
  return coef * abs(d) * d / (l2 + float(l2 == 0.0f));
}
