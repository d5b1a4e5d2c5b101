// Internal to the renderer: its GL objects (Renderer::Gl) and the buffer helper that
// renderer.cpp (models, snapshots, uploads) and renderer_draw.cpp (the passes) share.
#pragma once

#include <algorithm>
#include <cstring>
#include <vector>

#include "gl_program.hpp"
#include "maille/render/renderer.hpp"

namespace maille::render {

// GPU objects. Buffers are created with OpenGL 4.5 direct state access; the positions buffer is
// shared by every pass (storage buffer for links and points, vertex attribute for surfaces).
struct Renderer::Gl {
  GLuint background = 0, lines = 0, surface = 0, links = 0, points = 0, solid = 0;  // programs
  GLuint normals_pass = 0, bounds_pass = 0, contacts_pass = 0;                      // compute
  GLuint empty_vao = 0;    // passes that fetch everything from storage buffers
  GLuint surface_vao = 0;  // positions + normals + triangle indices
  GLuint lines_vao = 0;    // interleaved position, colour (grid, then overlay)
  GLuint positions = 0, normals = 0, triangles = 0, face_offset = 0, faces_of = 0;
  GLuint link_ends = 0, link_rest = 0, styles = 0, line_vertices = 0;
  GLuint contact_ends = 0, contact_threshold = 0;    // conditional links
  GLuint contacts_active = 0, contacts_command = 0;  // the active ones, and their draw command
  GLuint box = 0;                                    // the bounds pass's result: 2 vec4
  GLsync box_ready = nullptr;                        // set while a reduction is in flight
  GLsizei triangle_indices = 0;
  GLint links_off_surface = 0, links_total = 0;  // links [0, off) are not inside a cloth
  GLsizei contact_total = 0;
  GLsizei grid_vertices = 0, overlay_vertices = 0;
  std::vector<float> grid;  // interleaved x y z r g b

  // One solid mesh on the GPU: solid_vertices() in a buffer of its own, with its VAO.
  struct Solid {
    // Held, not just compared: while uploaded, no other mesh can be allocated at its address
    // and be mistaken for it.
    std::shared_ptr<const TriMesh> mesh;
    GLuint vao = 0, vertices = 0;
    GLsizei count = 0;
    Bounds box;  // in the mesh's frame
    bool closed = false;
  };
  std::vector<Solid> solids;  // a handful: found by a linear search

  // Smooth surfaces: the compute program and what it reads and writes (grids and PN triangles
  // per model; vertices and triangles per level of detail).
  GLuint smooth = 0, smooth_vao = 0;
  GLuint smooth_grids = 0, smooth_tris = 0, smooth_vertices = 0, smooth_indices = 0;
  int smooth_lod = 0;  // the level of detail the buffers are sized for; 0: none yet
  GLuint smooth_vertex_count = 0, smooth_grid_vertices = 0;
  GLsizei smooth_index_count = 0;
  void delete_smooth() {
    const GLuint b[] = {smooth_grids, smooth_tris, smooth_vertices, smooth_indices};
    glDeleteBuffers(4, b);
    smooth_grids = smooth_tris = smooth_vertices = smooth_indices = 0;
    smooth_lod = 0;
    smooth_vertex_count = smooth_grid_vertices = 0;
    smooth_index_count = 0;
  }

  ~Gl() {
    for (GLuint p : {background, lines, surface, links, points, solid, smooth, normals_pass,
                     bounds_pass, contacts_pass})
      glDeleteProgram(p);
    if (box_ready) glDeleteSync(box_ready);
    glDeleteBuffers(1, &box);
    const GLuint vaos[] = {empty_vao, surface_vao, lines_vao, smooth_vao};
    glDeleteVertexArrays(4, vaos);
    delete_smooth();
    delete_buffers();
    glDeleteBuffers(1, &line_vertices);
    for (Solid& s : solids) free(s);
  }
  static void free(Solid& s) {
    glDeleteVertexArrays(1, &s.vao);
    glDeleteBuffers(1, &s.vertices);
    s.vao = s.vertices = 0;
  }
  const Solid* find(const TriMesh* mesh) const {
    for (const Solid& s : solids)
      if (s.mesh.get() == mesh) return &s;
    return nullptr;
  }
  void delete_buffers() {
    const GLuint b[] = {positions, normals,     triangles, link_ends,    link_rest,
                        styles,    face_offset, faces_of,  contact_ends, contact_threshold};
    glDeleteBuffers(10, b);
    const GLuint c[] = {contacts_active, contacts_command};
    glDeleteBuffers(2, c);
    positions = normals = triangles = link_ends = link_rest = styles = 0;
    face_offset = faces_of = contact_ends = contact_threshold = 0;
    contacts_active = contacts_command = 0;
  }
};

// A buffer holding `data` (OpenGL 4.5 direct state access).
template <class T>
GLuint make_buffer(const std::vector<T>& data, GLbitfield flags = 0) {
  GLuint b = 0;
  glCreateBuffers(1, &b);
  // Zero-sized storage is an error: buffers get 16 bytes at least. An array smaller than that
  // (empty, or one link's 8 bytes) is copied into zero padding, never read past its end.
  const std::size_t size = data.size() * sizeof(T);
  const std::size_t bytes = std::max<std::size_t>(size, 16);
  std::vector<unsigned char> padded;
  const void* src = data.data();
  if (size < bytes) {
    padded.assign(bytes, 0);
    if (size > 0) std::memcpy(padded.data(), data.data(), size);
    src = padded.data();
  }
  glNamedBufferStorage(b, static_cast<GLsizeiptr>(bytes), src, flags);
  return b;
}

}  // namespace maille::render
