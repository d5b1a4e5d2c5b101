#include "kernel.hpp"

#include <epoxy/gl.h>

#include <utility>

#include "../render/gl_program.hpp"
#include "shaders.hpp"

namespace maille::gpu {

Kernel::Kernel(std::string_view name, const std::string& source)
    : program_(render::link_compute_program(name, source)) {}

Kernel::Kernel(Kernel&& o) noexcept
    : program_(std::exchange(o.program_, 0)), loc_(std::move(o.loc_)) {}

Kernel& Kernel::operator=(Kernel&& o) noexcept {
  std::swap(program_, o.program_);
  std::swap(loc_, o.loc_);
  return *this;
}

Kernel::~Kernel() {
  if (program_) glDeleteProgram(program_);
}

int Kernel::at(const char* name) {
  auto it = loc_.find(name);
  if (it == loc_.end()) it = loc_.emplace(name, glGetUniformLocation(program_, name)).first;
  return it->second;
}

void Kernel::set(const char* name, unsigned value) {
  glProgramUniform1ui(program_, at(name), value);
}
void Kernel::set(const char* name, float value) {
  glProgramUniform1f(program_, at(name), value);
}
void Kernel::set_flag(const char* name, bool value) {
  glProgramUniform1i(program_, at(name), value);
}
void Kernel::set(const char* name, const Vec3& value) {
  glProgramUniform3f(program_, at(name), float(value.x), float(value.y), float(value.z));
}
void Kernel::set(const char* name, const float (&value)[3]) {
  glProgramUniform3f(program_, at(name), value[0], value[1], value[2]);
}
void Kernel::set(const char* name, const float (&value)[4]) {
  glProgramUniform4f(program_, at(name), value[0], value[1], value[2], value[3]);
}

void Kernel::set(const char* name, const Mat3& value) {
  float rows[9];
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) rows[3 * i + j] = float(value.m[i][j]);
  glProgramUniformMatrix3fv(program_, at(name), 1, GL_TRUE, rows);  // row-major: transposed
}

void Kernel::run(unsigned count, unsigned groups) {
  if (groups == 0) return;
  set("u_count", count);
  glUseProgram(program_);
  glDispatchCompute(groups, 1, 1);
  glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);
}

void Kernel::run(unsigned count) {
  run(count, (count + kGroupSize - 1) / kGroupSize);
}

}  // namespace maille::gpu
