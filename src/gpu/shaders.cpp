#include "shaders.hpp"

#include "gpu_layout.hpp"
#include "shared_laws_glsl.hpp"

namespace maille::gpu {

namespace {

// The head of every kernel: version, work group, the records, the shared laws' prelude (the
// scalar is float here) and packed-vec3 helpers.
std::string head(std::initializer_list<Buf> used) {
  std::string s =
      "#version 450 core\nlayout(local_size_x = " + std::to_string(kGroupSize) + ") in;\n";
  s += glsl_records();
  s += glsl_buffers(used);
  s += R"(
#define real float
#define MAILLE_SHARED
#define MAILLE_UNUSED(x)
#define MAILLE_OUT(T) out T
#define MAILLE_INOUT(T) inout T
float largest_real() { return uintBitsToFloat(0x7f7fffffu); }
vec3 zero3() { return vec3(0.0); }
mat3 outer3(vec3 a, vec3 b) { return outerProduct(a, b); }
mat3 identity3() { return mat3(1.0); }
#define LOAD3(buf, i) vec3(buf[3u * (i)], buf[3u * (i) + 1u], buf[3u * (i) + 2u])
#define STORE3(buf, i, value) { vec3 s_ = (value); uint k_ = 3u * (i); \
  buf[k_] = s_.x; buf[k_ + 1u] = s_.y; buf[k_ + 2u] = s_.z; }
uniform uint u_count;  // points, faces or driven points: the invocations that work
)";
  return s;
}

}  // namespace

// The switch over the model's kinds, generated: kind k calls its shared law (with the form's
// suffix) with its first `fields` parameters, then the form's extra arguments.
std::string link_switch_function(const std::vector<KindLaw>& kinds, const LinkSwitch& form) {
  std::string s = std::string(form.type) + " " + std::string(form.name) +
                  "(uint kind, vec3 xa, vec3 xb, vec3 va, vec3 vb, vec4 p" +
                  std::string(form.extra_params) + ") {\n  switch (kind) {\n";
  const char* component[] = {"p.x", "p.y", "p.z", "p.w"};
  for (std::size_t k = 0; k < kinds.size(); ++k) {
    s += "    case " + std::to_string(k) + "u: return " + kinds[k].law + std::string(form.suffix) +
         "(xa, xb, va, vb";
    for (int f = 0; f < kinds[k].fields; ++f) s += std::string(", ") + component[f];
    s += std::string(form.extra_args) + ");\n";
  }
  s += "  }\n  return " + std::string(form.type) + "(0.0);\n}\n";
  return s;
}

std::string link_force_function(const std::vector<KindLaw>& kinds) {
  return link_switch_function(kinds, {"vec3", "link_force", "", "", ""});
}

std::string kernel_head(std::initializer_list<Buf> used) {
  return head(used);
}

std::string forces_shader(const std::vector<KindLaw>& kinds) {
  std::string s =
      head({Buf::x, Buf::v, Buf::f, Buf::inv_mass, Buf::mass, Buf::adjacency_offset, Buf::adjacency,
            Buf::link_params, Buf::face_offset, Buf::face_of_point, Buf::face_force});
  s += shared::link_laws;
  s += link_force_function(kinds);
  s += R"(
uniform vec3 u_gravity;  // m/s^2
uniform float u_drag;    // 1/s
uniform bool u_wind;     // face forces to sum
uniform uint u_base;     // the first point of this dispatch (the structured layout runs grids)
void main() {
  if (gl_GlobalInvocationID.x >= u_count) return;
  uint i = u_base + gl_GlobalInvocationID.x;
  vec3 xi = LOAD3(x, i);
  vec3 vi = LOAD3(v, i);
  vec3 fi = vec3(0.0);
  uint end = adjacency_offset[i + 1u];
  for (uint e = adjacency_offset[i]; e < end; ++e) {
    Adjacent l = adjacency[e];
    vec3 xj = LOAD3(x, l.other);
    vec3 vj = LOAD3(v, l.other);
    vec4 p = vec4(link_params[4u * l.params], link_params[4u * l.params + 1u],
                  link_params[4u * l.params + 2u], link_params[4u * l.params + 3u]);
    // The law gives the force on the link's a end; its b end gets the opposite.
    if ((l.kind & 0x80000000u) != 0u)
      fi -= link_force(l.kind & 0x7fffffffu, xj, xi, vj, vi, p);
    else
      fi += link_force(l.kind, xi, xj, vi, vj, p);
  }
  if (u_wind) {
    uint face_end = face_offset[i + 1u];
    for (uint e = face_offset[i]; e < face_end; ++e) fi += LOAD3(face_force, face_of_point[e]);
  }
  if (inv_mass[i] > 0.0) fi += (u_gravity - vi * u_drag) * mass[i];
  STORE3(f, i, fi);
}
)";
  return s;
}

std::string faces_shader() {
  std::string s = head({Buf::x, Buf::v, Buf::face_corner, Buf::face_force});
  s += shared::wind_law;
  s += R"(
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
)";
  return s;
}

std::string integrate_shader() {
  std::string s = head({Buf::x, Buf::v, Buf::f, Buf::inv_mass, Buf::health});
  s += R"(
uniform float u_kick;   // s
uniform float u_drift;  // s
uniform uint u_step;    // the step count after this step (the health flag's value)
void main() {
  uint i = gl_GlobalInvocationID.x;
  if (i >= u_count) return;
  float w = inv_mass[i];
  vec3 vi = LOAD3(v, i) + LOAD3(f, i) * (w * u_kick);
  vec3 xi = LOAD3(x, i) + vi * (w > 0.0 ? u_drift : 0.0);
  STORE3(v, i, vi);
  STORE3(x, i, xi);
  if (any(isnan(xi)) || any(isinf(xi)) || any(isnan(vi)) || any(isinf(vi)))
    atomicMin(health[0], u_step);
}
)";
  return s;
}

std::string drive_shader() {
  std::string s = head({Buf::x, Buf::v, Buf::driven});
  s += R"(
void main() {
  uint k = gl_GlobalInvocationID.x;
  if (k >= u_count) return;
  DrivenPoint d = driven[k];
  STORE3(x, d.point, vec3(d.px, d.py, d.pz));
  STORE3(v, d.point, vec3(d.vx, d.vy, d.vz));
}
)";
  return s;
}

}  // namespace maille::gpu
