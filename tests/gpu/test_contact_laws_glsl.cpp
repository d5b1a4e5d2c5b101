// The contact laws' GLSL (include/maille/detail/contact_laws.glsl, the very file the C++ build
// includes) compiled by the OpenGL driver and evaluated in a compute shader, against the C++
// laws on the same inputs. The GPU computes in float: inputs are rounded to float first, and the
// tolerances are float's rounding carried through a few operations on values of order 1
// (closest points) or through k s (forces): 1e-4 relative, a hundred float units.
#include <epoxy/gl.h>
#include <gtest/gtest.h>

#include <array>
#include <fstream>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "maille/render/headless.hpp"
#include "maille/shared_laws.hpp"

namespace maille {
namespace {

std::string law_text() {
  std::ifstream in(MAILLE_SOURCE_DIR "/include/maille/detail/contact_laws.glsl");
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

// One invocation per case: 4 points (12 floats) and a velocity difference in; the triangle
// weights, the edge parameters, the edge pair's force and block diagonal out (10 floats).
const char* kMain = R"(
layout(std430, binding = 0) readonly buffer In { float in_[]; };
layout(std430, binding = 1) writeonly buffer Out { float out_[]; };
uniform uint u_count;
vec3 at(uint c, uint k) { uint b = 15u * c + 3u * k; return vec3(in_[b], in_[b + 1u], in_[b + 2u]); }
void main() {
  uint c = gl_GlobalInvocationID.x;
  if (c >= u_count) return;
  vec3 w = triangle_closest_weights(at(c, 0u), at(c, 1u), at(c, 2u), at(c, 3u));
  float s; float t;
  edge_edge_params(at(c, 0u), at(c, 1u), at(c, 2u), at(c, 3u), s, t);
  vec3 d = at(c, 0u) * (1.0 - s) + at(c, 1u) * s - (at(c, 2u) * (1.0 - t) + at(c, 3u) * t);
  vec3 f = stencil_contact_force(d, at(c, 4u), 800.0, 3.0, 2.0);
  mat3 b = stencil_contact_block(d, 800.0, 3.0, 2.0, 60.0);
  float o[13] = float[13](w.x, w.y, w.z, s, t, f.x, f.y, f.z, b[0][0], b[1][1], b[2][2],
                          contact_energy(length(d), 800.0, 2.0), edge_edge_interior(s, t) ? 1.0 : 0.0);
  for (uint k = 0u; k < 13u; ++k) out_[13u * c + k] = o[k];
}
)";

GLuint compile(const std::string& source) {
  const GLuint shader = glCreateShader(GL_COMPUTE_SHADER);
  const char* text = source.c_str();
  glShaderSource(shader, 1, &text, nullptr);
  glCompileShader(shader);
  GLint ok = 0;
  glGetShaderiv(shader, GL_COMPILE_STATUS, &ok);
  if (!ok) {
    char log[4096];
    glGetShaderInfoLog(shader, sizeof log, nullptr, log);
    ADD_FAILURE() << log;
  }
  const GLuint program = glCreateProgram();
  glAttachShader(program, shader);
  glLinkProgram(program);
  glDeleteShader(shader);
  return program;
}

TEST(ContactLawsGlsl, TheSameFileGivesTheSameValuesOnTheGpu) {
  render::HeadlessContext context;
  const std::string source = std::string("#version 450 core\nlayout(local_size_x = 64) in;\n") +
                             "#define real float\n#define MAILLE_SHARED\n#define MAILLE_UNUSED(x)\n"
                             "#define MAILLE_OUT(T) out T\n#define MAILLE_INOUT(T) inout T\n"
                             "vec3 zero3() { return vec3(0.0); }\n"
                             "mat3 outer3(vec3 a, vec3 b) { return outerProduct(a, b); }\n"
                             "mat3 identity3() { return mat3(1.0); }\n" +
                             law_text() + kMain;
  const GLuint program = compile(source);
  ASSERT_NE(program, 0u);

  // Random stencils of points within 1 m, a few parallel edge pairs among them.
  std::mt19937 rng(5);
  std::uniform_real_distribution<float> u(-1, 1);
  constexpr unsigned kCases = 512;
  std::vector<float> in(15 * kCases);
  for (float& x : in) x = u(rng);
  for (unsigned c = 0; c < kCases; c += 16)  // b0b1 parallel to a0a1, offset
    for (int k = 0; k < 3; ++k) {
      in[15 * c + 9 + std::size_t(k)] =
          in[15 * c + 6 + std::size_t(k)] +
          (in[15 * c + 3 + std::size_t(k)] - in[15 * c + std::size_t(k)]);
    }
  GLuint buffers[2];
  glCreateBuffers(2, buffers);
  glNamedBufferData(buffers[0], GLsizeiptr(in.size() * sizeof(float)), in.data(), GL_STATIC_DRAW);
  glNamedBufferData(buffers[1], GLsizeiptr(13 * kCases * sizeof(float)), nullptr, GL_STATIC_READ);
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 0, buffers[0]);
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 1, buffers[1]);
  glUseProgram(program);
  glUniform1ui(glGetUniformLocation(program, "u_count"), kCases);
  glDispatchCompute(kCases / 64, 1, 1);
  glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
  std::vector<float> out(13 * kCases);
  glGetNamedBufferSubData(buffers[1], 0, GLsizeiptr(out.size() * sizeof(float)), out.data());
  glDeleteBuffers(2, buffers);
  glDeleteProgram(program);

  int compared = 0, touching = 0;
  for (unsigned c = 0; c < kCases; ++c) {
    auto p = [&](int k) {
      const float* q = &in[15 * c + 3 * std::size_t(k)];
      return Vec3{q[0], q[1], q[2]};
    };
    const float* o = &out[13 * c];
    const Vec3 w = law::triangle_closest_weights(p(0), p(1), p(2), p(3));
    EXPECT_NEAR(o[0], w.x, 1e-4) << c;
    EXPECT_NEAR(o[1], w.y, 1e-4) << c;
    EXPECT_NEAR(o[2], w.z, 1e-4) << c;
    Real s = 0, t = 0;
    law::edge_edge_params(p(0), p(1), p(2), p(3), s, t);
    // Near a region's boundary float may pick the neighbouring branch: the closest points then
    // differ by the branch's rounding, not by the law (counted, and nearly every case compared).
    if (std::abs(o[3] - s) > 1e-3 || std::abs(o[4] - t) > 1e-3) continue;
    ++compared;
    const Vec3 d = p(0) * (1 - s) + p(1) * s - (p(2) * (1 - t) + p(3) * t);
    const Vec3 f = law::stencil_contact_force(d, p(4), 800, 3, 2);
    const Mat3 b = law::stencil_contact_block(d, 800, 3, 2, 60);
    const double scale = 800 * 2 + 3 * norm(p(4));
    EXPECT_NEAR(o[5], f.x, 1e-3 * scale) << c;
    EXPECT_NEAR(o[6], f.y, 1e-3 * scale) << c;
    EXPECT_NEAR(o[7], f.z, 1e-3 * scale) << c;
    EXPECT_NEAR(o[8], b.m[0][0], 1e-4 * 980) << c;
    EXPECT_NEAR(o[9], b.m[1][1], 1e-4 * 980) << c;
    EXPECT_NEAR(o[10], b.m[2][2], 1e-4 * 980) << c;
    EXPECT_NEAR(o[11], law::contact_energy(norm(d), 800, 2), 1e-3 * 800 * 4) << c;
    EXPECT_EQ(o[12] != 0, law::edge_edge_interior(s, t)) << c;
    touching += norm(d) < 2;
  }
  EXPECT_GE(compared, int(kCases * 0.95));
  EXPECT_GT(touching, int(kCases / 2));  // the radius 2 m takes in most pairs: forces compared
}

}  // namespace
}  // namespace maille
