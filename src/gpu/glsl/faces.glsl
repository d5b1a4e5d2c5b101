// The body of faces_shader (src/gpu/shaders.cpp, which puts the kernel's head, buffers and laws
// before it).
uniform vec3 u_mean;     // U, m/s
uniform float u_coef;    // rho C_d / 12
uniform bool u_gusty;
uniform vec3 u_k_along;  // u / lambda, 1/m
uniform vec3 u_k_across; // e2 / lambda, 1/m
uniform vec4 u_phase;    // each sine's phase at t, reduced to [-1/2, 1/2] turn on the host
uniform vec3 u_along;    // the gust's amplitude vectors, m/s (gust::Basis)
uniform vec3 u_across1;
uniform vec3 u_across2;
float reduce_turn(float y) { return y - roundEven(y); }
void main() {
  uint k = gl_GlobalInvocationID.x;
  if (k >= u_count) return;
  uint a = face_corner[3u * k], b = face_corner[3u * k + 1u], c = face_corner[3u * k + 2u];
  vec3 xa = LOAD3(x, a), xb = LOAD3(x, b), xc = LOAD3(x, c);
  vec3 a2 = cross(xb - xa, xc - xa);
  vec3 vc = (LOAD3(v, a) + LOAD3(v, b) + LOAD3(v, c)) * (1.0 / 3.0);
  vec3 w = u_mean;
  if (u_gusty) {
    vec3 centre = (xa + xb + xc) * (1.0 / 3.0);
    float s = dot(u_k_along, centre), q = dot(u_k_across, centre);
    float s0 = sin_half_turn(reduce_turn(u_phase.x + MAILLE_GUST_WAVE0(s, q)));
    float s1 = sin_half_turn(reduce_turn(u_phase.y + MAILLE_GUST_WAVE1(s, q)));
    float s2 = sin_half_turn(reduce_turn(u_phase.z + MAILLE_GUST_WAVE2(s, q)));
    float s3 = sin_half_turn(reduce_turn(u_phase.w + MAILLE_GUST_WAVE3(s, q)));
    w += u_along * gust_along_factor(s0, s1) + u_across1 * s2 + u_across2 * s3;
  }
  STORE3(face_force, k, a2 * wind_pressure_scale(u_coef, dot(w - vc, a2), dot(a2, a2)));
}
