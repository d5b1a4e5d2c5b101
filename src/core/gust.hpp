// The gust field of WindField and the wind's pressure law on one face, written so that the wind
// stage can evaluate them in vectorised loops. Internal to the core: WindField::at (wind.cpp) and
// the wind stage (field_forces.cpp) share them.
//
// Why this shape: evaluated per face as WindField::at(p, t), the field rebuilt its basis (a norm,
// a cross product, a square root and four divisions) and ran four scalar sines with a branchy
// range reduction for every face: 80 % of the default scene's step. Here everything that does
// not depend on the point is computed once per evaluation of the forces (Basis: the wave vectors,
// each sine's phase at time t, the gust's amplitudes as vectors), and the per-point part is
// branch-free, division-free and inlined, so face loops vectorise, in two halves of one width
// each: arguments (double: the phases grow with time and positions need their digits), reduced
// to half a turn and rounded to float; then gust_from (float: the four sines' polynomial and
// their weighted sum, the gust w - U). The field is the original formula (test
// unit.Wind.GustFieldMatchesTheReferenceFormula) up to float rounding of the sines and of their
// sum: below 1e-6 of the gusts' amplitude T |U|.
#pragma once

#include <cmath>
#include <numbers>

#include "maille/fields.hpp"
#include "maille/shared_laws.hpp"

namespace maille::gust {

// sin(2 pi y), y in turns (|y| < 2^51), to float rounding (the unit test bounds the field's
// error and measures it), in two halves so that a loop can run each with one width: reduce
// (double in, float out) and sin_half (float only). Branch-free so that loops vectorise:
// - the nearest integer k: std::nearbyint where it is one instruction (SSE4.1 roundpd), else the
//   magic-number trick (y + 1.5 2^52) - 1.5 2^52, which rounds to nearest-even exactly as
//   nearbyint does for |y| < 2^51; r = y - k in [-1/2, 1/2] is exact in double, then rounded
//   once to float;
// - the two folds as compare-selects: r > 1/4 becomes 1/2 - r, r < -1/4 becomes -1/2 - r (exact
//   in float), so 2 pi r lies in [-pi/2, pi/2];
// - an odd polynomial of degree 9 in r, fitted to sin(2 pi r) on [-1/4, 1/4] (near-minimax:
//   error 3.3e-9, against 5.7e-8 for the Taylor polynomial of degree 11 of the first version of
//   the field), in float (the field needs smoothness, not the last bits, and float halves the
//   cost), by Estrin's scheme: short chains instead of Horner's long one, so that the processor
//   overlaps them (the loop was bound by that latency).
inline float reduce(double y) {
#ifdef __SSE4_1__
  const double k = std::nearbyint(y);  // one instruction (roundpd), the same integer
#else
  constexpr double magic = 0x1.8p52;
  const double k = (y + magic) - magic;
#endif
  return static_cast<float>(y - k);
}

inline float sin_half(float r) {
  return law::sin_half_turn(r);  // include/maille/detail/wind_law.glsl
}

inline float sin_turns(double y) {
  return sin_half(reduce(y));
}

// The point-independent part of the field at time t.
//   w(p, t) = U + T U (0.6 S0 + 0.4 S1) + 0.5 T |U| e1 S2 + 0.3 T |U| e2 S3,
//   S_k = sin(2 pi (phase_k - a_k s + b_k q)), s = u.p / lambda, q = e2.p / lambda
// (u along U, e1 across it and horizontal, e2 the third), which is the formula of WindField
// (fields.hpp) with its products expanded: U (1 + T g) + T |U| (c1 e1 + c2 e2).
struct Basis {
  bool steady = true;          // no gusts (no wind or no turbulence): w = mean everywhere
  Vec3 mean{};                 // U, m/s
  Vec3 k_along{}, k_across{};  // u / lambda and e2 / lambda, 1/m
  double phase[4] = {};        // f t times each sine's frequency factor, plus its phase, turns
  // The gust is along * (0.6 S0 + 0.4 S1) + across1 * S2 + across2 * S3, by axis:
  float along[3] = {};    // T U, m/s
  float across1[3] = {};  // 0.5 T |U| e1, m/s
  float across2[3] = {};  // 0.3 T |U| e2, m/s
};

// Each sine's frequency factor and phase (rad); its wave numbers along and across the wind (in
// 1/lambda: 1, 1.31, 0.8, 1.2 and 0, 0.5, 0.3, 0) are MAILLE_GUST_WAVEk in wind_law.glsl. The
// incommensurate factors (1.73, 1.37, 0.61) keep the pattern from repeating quickly.
inline constexpr double frequency_factor[4] = {1, 1.73, 1.37, 0.61};
inline constexpr double phase_rad[4] = {0, 1.1, 0.7, 2.1};

inline Basis basis(const WindField& w, double t) {
  Basis b;
  b.mean = w.velocity;
  const Real speed = norm(w.velocity);
  if (speed == 0 || w.turbulence == 0) return b;
  b.steady = false;
  const Vec3 u = w.velocity / speed;
  Vec3 e1 = cross(u, Vec3{0, 1, 0});
  if (norm2(e1) < Real(1e-12)) e1 = Vec3{1, 0, 0};
  e1 = e1 / norm(e1);
  const Vec3 e2 = cross(e1, u);
  b.k_along = u / w.gust_wavelength;
  b.k_across = e2 / w.gust_wavelength;
  const double ft = w.gust_frequency * t;
  for (int k = 0; k < 4; ++k)
    b.phase[k] = frequency_factor[k] * ft + phase_rad[k] / (2 * std::numbers::pi);
  const Real cross_amplitude = w.turbulence * speed;
  const Vec3 along = w.velocity * w.turbulence, across1 = e1 * Real(0.5 * cross_amplitude),
             across2 = e2 * Real(0.3 * cross_amplitude);
  for (int axis = 0; axis < 3; ++axis) {
    b.along[axis] = float(along[axis]);
    b.across1[axis] = float(across1[axis]);
    b.across2[axis] = float(across2[axis]);
  }
  return b;
}

// Gusts are a fixed sum of travelling sines along the wind and across it: smooth in space and
// time, deterministic (same scene, same trajectory), and rich enough that a flag never settles.
// The arguments are in turns: the original radians tau (f t c_k - a_k s + b_k q) + phase_k.
// All three require !b.steady (then the field is b.mean).
//
// The four sines' arguments at p, reduced to [-1/2, 1/2] turn (reduce), from p's coordinates
// along and across the wind in wavelengths, s = u.p / lambda and q = e2.p / lambda (linear in
// p: the stage gives a face the mean of its corners' s and q).
inline void arguments(const Basis& b, double s, double q, float r[4]) {
  r[0] = reduce(b.phase[0] + MAILLE_GUST_WAVE0(s, q));  // include/maille/detail/wind_law.glsl
  r[1] = reduce(b.phase[1] + MAILLE_GUST_WAVE1(s, q));
  r[2] = reduce(b.phase[2] + MAILLE_GUST_WAVE2(s, q));
  r[3] = reduce(b.phase[3] + MAILLE_GUST_WAVE3(s, q));
}

inline void arguments(const Basis& b, const Vec3& p, float r[4]) {
  arguments(b, dot(b.k_along, p), dot(b.k_across, p), r);
}

// The gust w - U (m/s, by axis) from the four reduced arguments.
inline void gust_from(const Basis& b, const float r[4], float gust[3]) {
  const float s0 = sin_half(r[0]), s1 = sin_half(r[1]), s2 = sin_half(r[2]), s3 = sin_half(r[3]);
  const float g = law::gust_along_factor(s0, s1);
  for (int axis = 0; axis < 3; ++axis)
    gust[axis] = (b.along[axis] * g + b.across1[axis] * s2) + b.across2[axis] * s3;
}

inline Vec3 at(const Basis& b, const Vec3& p) {
  float r[4], gust[3];
  arguments(b, p, r);
  gust_from(b, r, gust);
  return {b.mean.x + Real(gust[0]), b.mean.y + Real(gust[1]), b.mean.z + Real(gust[2])};
}

// The wind's force on each corner of one face (N), from its doubled area vector
// a2 = (x_b - x_a) x (x_c - x_a) = 2 A n, the mean of its corners' velocities vc and the air
// velocity w at its centre:
//   F = 1/2 rho C_d A |v_rel . n| (v_rel . n) n / 3,  v_rel = w - vc
//     = coef |d| d / |a2|^2 a2,  d = v_rel . a2,  coef = rho C_d / 12
// (no square root: A = |a2| / 2 and n = a2 / |a2|). A degenerate face (a2 = 0) gets no force:
// the division is by |a2|^2 + (|a2|^2 == 0), written so that loops vectorise without masks.
// The factor of a2 in it, from d and |a2|^2: shared by the double path below and the grid path's
// float loop (field_forces.cpp), which writes the vectors out by component.
// float: the shared law (wind_law.glsl); double (the general path): the same formula.
inline float face_force_scale(float coef, float d, float l2) {
  return law::wind_pressure_scale(coef, d, l2);
}
inline double face_force_scale(double coef, double d, double l2) {
  return coef * std::abs(d) * d / (l2 + double(l2 == 0));
}
inline Vec3 face_force(const Vec3& w, Real coef, const Vec3& a2, const Vec3& vc) {
  return a2 * face_force_scale(coef, dot(w - vc, a2), norm2(a2));
}

}  // namespace maille::gust
