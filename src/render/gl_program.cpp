#include "gl_program.hpp"

#include <initializer_list>
#include <stdexcept>
#include <string>

namespace maille::render {

namespace {

std::string shader_log(GLuint shader) {
  GLint length = 0;
  glGetShaderiv(shader, GL_INFO_LOG_LENGTH, &length);
  std::string log(static_cast<std::size_t>(std::max(length, 1)), '\0');
  glGetShaderInfoLog(shader, length, nullptr, log.data());
  return log;
}

GLuint compile(std::string_view pass, GLenum type, std::string_view source) {
  const GLuint shader = glCreateShader(type);
  const char* text = source.data();
  const auto length = static_cast<GLint>(source.size());
  glShaderSource(shader, 1, &text, &length);
  glCompileShader(shader);
  GLint ok = GL_FALSE;
  glGetShaderiv(shader, GL_COMPILE_STATUS, &ok);
  if (!ok) {
    const std::string log = shader_log(shader);
    glDeleteShader(shader);
    throw std::runtime_error("renderer: " + std::string(pass) +
                             (type == GL_VERTEX_SHADER    ? " vertex"
                              : type == GL_COMPUTE_SHADER ? " compute"
                                                          : " fragment") +
                             " shader: " + log);
  }
  return shader;
}

GLuint link(std::string_view pass, std::initializer_list<GLuint> shaders);

}  // namespace

GLuint link_program(std::string_view pass, std::string_view vertex_source,
                    std::string_view fragment_source) {
  const GLuint vs = compile(pass, GL_VERTEX_SHADER, vertex_source);
  const GLuint fs = compile(pass, GL_FRAGMENT_SHADER, fragment_source);
  return link(pass, {vs, fs});
}

GLuint link_compute_program(std::string_view pass, std::string_view compute_source) {
  return link(pass, {compile(pass, GL_COMPUTE_SHADER, compute_source)});
}

namespace {

GLuint link(std::string_view pass, std::initializer_list<GLuint> shaders) {
  const GLuint program = glCreateProgram();
  for (GLuint sh : shaders) glAttachShader(program, sh);
  glLinkProgram(program);
  for (GLuint sh : shaders) glDeleteShader(sh);
  GLint ok = GL_FALSE;
  glGetProgramiv(program, GL_LINK_STATUS, &ok);
  if (!ok) {
    GLint length = 0;
    glGetProgramiv(program, GL_INFO_LOG_LENGTH, &length);
    std::string log(static_cast<std::size_t>(std::max(length, 1)), '\0');
    glGetProgramInfoLog(program, length, nullptr, log.data());
    glDeleteProgram(program);
    throw std::runtime_error("renderer: " + std::string(pass) + " program: " + log);
  }
  return program;
}

}  // namespace

}  // namespace maille::render
