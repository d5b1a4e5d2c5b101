// Storage buffers from host vectors: the one upload of the GPU backend's files (the step's
// buffers, self-collision's grid, the structured layout, VBD and its obstacles). The context
// must be current.
#pragma once

#include <epoxy/gl.h>

#include <array>
#include <cstddef>
#include <cstring>
#include <vector>

namespace maille::gpu {

// `data` into `buffer` (glNamedBufferData), padded with zeros to at least 16 bytes: a buffer
// bound to a storage block must not be empty. `usage` is GL's hint: GL_DYNAMIC_DRAW for what
// the step rewrites, GL_STATIC_DRAW for what is written once.
template <class T>
void upload(GLuint buffer, const std::vector<T>& data, GLenum usage = GL_DYNAMIC_DRAW) {
  const std::size_t bytes = data.size() * sizeof(T);
  if (bytes >= 16) {
    glNamedBufferData(buffer, GLsizeiptr(bytes), data.data(), usage);
    return;
  }
  std::array<std::byte, 16> padded{};
  if (bytes) std::memcpy(padded.data(), data.data(), bytes);
  glNamedBufferData(buffer, GLsizeiptr(padded.size()), padded.data(), usage);
}

}  // namespace maille::gpu
