#include "maille/render/renderer.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <memory>
#include <stdexcept>
#include <string>

#include "gl_program.hpp"
#include "shaders.hpp"
#include "smooth_shader.hpp"

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

namespace {

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

// Steps of 1, 2 or 5 times a power of ten: grid spacings a reader can count in.
double nice_step(double rough) {
  const double decade = std::pow(10.0, std::floor(std::log10(rough)));
  for (double m : {1.0, 2.0, 5.0})
    if (m * decade >= rough) return m * decade;
  return 10 * decade;
}

// A square floor grid centred under the box, at its lowest height, about 20 cells wide.
std::vector<float> floor_grid(const Bounds& box) {
  std::vector<float> v;
  if (box.empty()) return v;
  const Vec3 c = box.centre();
  const double size =
      std::max({box.hi.x - box.lo.x, box.hi.z - box.lo.z, 0.5 * box.diagonal(), 1e-3});
  const double step = nice_step(size * 1.6 / 20);
  const int half = static_cast<int>(std::ceil(size * 0.8 / step));
  const double cx = std::round(c.x / step) * step, cz = std::round(c.z / step) * step;
  const float y = float(box.lo.y);
  auto vertex = [&](double x, double z, bool axis) {
    const float shade = axis ? 0.35f : 0.52f;
    v.insert(v.end(), {float(x), y, float(z), shade, shade, shade + 0.02f});
  };
  for (int i = -half; i <= half; ++i) {
    const double x = cx + i * step, z = cz + i * step;
    const bool axis = i == 0;
    vertex(x, cz - half * step, axis);
    vertex(x, cz + half * step, axis);
    vertex(cx - half * step, z, axis);
    vertex(cx + half * step, z, axis);
  }
  return v;
}

void set_uniform(GLuint program, const char* name, const Mat4& m) {
  glProgramUniformMatrix4fv(program, glGetUniformLocation(program, name), 1, GL_FALSE, m.m.data());
}

// The world box of a box placed by x -> direct x + translation: its 8 corners placed. Empty when
// the placement is not finite (a blown-up driven motion): nothing to frame.
Bounds placed_box(const Bounds& box, const SurfaceInstance& s) {
  Bounds out;
  if (box.empty()) return out;
  for (int c = 0; c < 8; ++c) {
    const Vec3 corner{(c & 1) ? box.hi.x : box.lo.x, (c & 2) ? box.hi.y : box.lo.y,
                      (c & 4) ? box.hi.z : box.lo.z};
    const Vec3 p = s.direct * corner + s.translation;
    if (!is_finite(p)) return {};
    out.add(p);
  }
  return out;
}

// Cloth faces (flat or smooth: a VAO of positions and normals, indexed triangles), lit on both
// sides, pushed back a little so that links lying on the cloth win the depth test.
void draw_cloth(GLuint program, const Mat4& view_proj, const Mat4& view, GLuint vao,
                GLsizei indices) {
  glUseProgram(program);
  set_uniform(program, "u_view_proj", view_proj);
  set_uniform(program, "u_view", view);
  glEnable(GL_POLYGON_OFFSET_FILL);
  glPolygonOffset(1.0f, 1.0f);
  glBindVertexArray(vao);
  glDrawElements(GL_TRIANGLES, indices, GL_UNSIGNED_INT, nullptr);
  glDisable(GL_POLYGON_OFFSET_FILL);
}

Real determinant(const Mat3& a) {
  return dot(Vec3{a.m[0][0], a.m[0][1], a.m[0][2]},
             cross(Vec3{a.m[1][0], a.m[1][1], a.m[1][2]}, Vec3{a.m[2][0], a.m[2][1], a.m[2][2]}));
}

}  // namespace

Renderer::Renderer() : gl_(std::make_unique<Gl>()) {
  Gl& g = *gl_;
  g.background = link_program("background", shaders::background_vs, shaders::background_fs);
  g.lines = link_program("lines", shaders::lines_vs, shaders::lines_fs);
  g.surface = link_program("surface", shaders::surface_vs, shaders::surface_fs);
  g.links = link_program("links", shaders::links_vs, shaders::links_fs);
  g.points = link_program("points", shaders::points_vs, shaders::points_fs);
  g.solid = link_program("solid", shaders::solid_vs, shaders::solid_fs);
  g.smooth = link_compute_program("smooth surface", shaders::smooth_cs());
  g.normals_pass = link_compute_program("vertex normals", shaders::normals_cs);
  g.bounds_pass = link_compute_program("bounds", shaders::bounds_cs);
  g.contacts_pass = link_compute_program("active contacts", shaders::contacts_cs);
  g.box = make_buffer(std::vector<float>(8, 0.0f));
  glCreateVertexArrays(1, &g.smooth_vao);
  for (GLuint attrib : {0u, 1u}) {  // interleaved position, normal (6 floats)
    glEnableVertexArrayAttrib(g.smooth_vao, attrib);
    glVertexArrayAttribFormat(g.smooth_vao, attrib, 3, GL_FLOAT, GL_FALSE, attrib * 12);
    glVertexArrayAttribBinding(g.smooth_vao, attrib, 0);
  }
  glCreateVertexArrays(1, &g.empty_vao);
  glCreateVertexArrays(1, &g.surface_vao);
  glCreateVertexArrays(1, &g.lines_vao);
  glCreateBuffers(1, &g.line_vertices);
  for (GLuint attrib : {0u, 1u}) {
    glEnableVertexArrayAttrib(g.lines_vao, attrib);
    glVertexArrayAttribFormat(g.lines_vao, attrib, 3, GL_FLOAT, GL_FALSE, attrib * 3 * 4);
    glVertexArrayAttribBinding(g.lines_vao, attrib, 0);
    glEnableVertexArrayAttrib(g.surface_vao, attrib);
    glVertexArrayAttribFormat(g.surface_vao, attrib, 3, GL_FLOAT, GL_FALSE, 0);
    glVertexArrayAttribBinding(g.surface_vao, attrib, attrib);
  }
}

Renderer::~Renderer() = default;

void Renderer::set_model(const Model& model) {
  Gl& g = *gl_;
  topology_ = make_topology(model);
  positions_ = model.points.initial_position;
  info_ = Snapshot{};
  device_positions_ = 0;
  device_bounds_ = {};
  g.delete_buffers();
  g.delete_smooth();
  smooth_ = SmoothSurface(model);
  // The old scene's obstacles go with it; the new ones come with the first snapshot.
  solids_.clear();
  upload_solids();

  // Links not inside a cloth first, so that "links off the surface" is a prefix of the array.
  const std::size_t n_links = topology_.link_rest.size();
  std::vector<std::uint32_t> order(n_links);
  for (std::size_t l = 0; l < n_links; ++l) order[l] = static_cast<std::uint32_t>(l);
  std::stable_partition(order.begin(), order.end(),
                        [&](std::uint32_t l) { return !topology_.link_on_surface[l]; });
  std::vector<std::uint32_t> ends(2 * n_links);
  std::vector<float> rest(n_links);
  for (std::size_t k = 0; k < n_links; ++k) {
    ends[2 * k] = topology_.link_ends[2 * order[k]];
    ends[2 * k + 1] = topology_.link_ends[2 * order[k] + 1];
    rest[k] = topology_.link_rest[order[k]];
  }
  g.links_total = static_cast<GLint>(n_links);
  g.links_off_surface = static_cast<GLint>(
      std::count(topology_.link_on_surface.begin(), topology_.link_on_surface.end(), 0));

  g.positions = make_buffer(std::vector<float>(positions_.size() * 3), GL_DYNAMIC_STORAGE_BIT);
  g.normals = make_buffer(std::vector<float>(positions_.size() * 3));
  g.triangles = make_buffer(topology_.triangles);
  g.triangle_indices = static_cast<GLsizei>(topology_.triangles.size());
  // The faces around each point (CSR), for the normals pass's gather.
  std::vector<std::uint32_t> face_offset(positions_.size() + 1, 0);
  std::vector<std::uint32_t> faces_of(topology_.triangles.size());
  for (std::uint32_t i : topology_.triangles) ++face_offset[i + 1];
  for (std::size_t p = 0; p < positions_.size(); ++p) face_offset[p + 1] += face_offset[p];
  std::vector<std::uint32_t> fill(face_offset.begin(), face_offset.end() - 1);
  for (std::size_t k = 0; k < topology_.triangles.size(); ++k)
    faces_of[fill[topology_.triangles[k]]++] = static_cast<std::uint32_t>(k / 3);
  g.face_offset = make_buffer(face_offset);
  g.faces_of = make_buffer(faces_of);
  g.contact_ends = make_buffer(topology_.contact_ends);
  g.contact_threshold = make_buffer(topology_.contact_threshold);
  g.contact_total = static_cast<GLsizei>(topology_.contact_threshold.size());
  g.contacts_active = make_buffer(std::vector<std::uint32_t>(topology_.contact_ends.size()));
  g.contacts_command = make_buffer(std::vector<std::uint32_t>{0, 1, 0, 0}, GL_DYNAMIC_STORAGE_BIT);
  g.link_ends = make_buffer(ends);
  g.link_rest = make_buffer(rest);
  g.styles = make_buffer(topology_.point_style);
  glVertexArrayVertexBuffer(g.surface_vao, 0, g.positions, 0, 12);
  glVertexArrayVertexBuffer(g.surface_vao, 1, g.normals, 0, 12);
  glVertexArrayElementBuffer(g.surface_vao, g.triangles);

  grid_box_ = bounds_of(positions_);
  g.grid = floor_grid(grid_box_);
  g.grid_vertices = static_cast<GLsizei>(g.grid.size() / 6);
  overlay_.clear();
  upload_lines();
  upload_positions();
}

void Renderer::set_snapshot(const Snapshot& snapshot) {
  if (snapshot.point_count() != positions_.size())
    throw std::invalid_argument("renderer: snapshot has " + std::to_string(snapshot.point_count()) +
                                " points, the model " + std::to_string(positions_.size()));
  info_.frame = snapshot.frame;
  info_.step = snapshot.step;
  info_.time = snapshot.time;
  device_positions_ = snapshot.device.gl_buffer;
  if (device_positions_ == 0) {
    std::copy(snapshot.positions.begin(), snapshot.positions.end(), positions_.begin());
    upload_positions();
  } else {
    positions_changed();
  }
  solids_ = snapshot.surfaces;
  upload_solids();
  if (device_positions_ == 0) lower_grid(bounds_of(positions_));
}

// A chain swinging down or a net sagging goes below its initial box: the floor follows (by steps
// of 5% of the box, so that it does not creep every frame). Solids count too (open ones as well:
// a ground plane puts the grid under it, not through it).
void Renderer::lower_grid(const Bounds& positions_box) {
  Bounds now = positions_box;
  for (const SurfaceInstance& s : solids_)
    if (const Gl::Solid* solid = gl_->find(s.mesh.get())) now.add(placed_box(solid->box, s));
  if (!now.empty() && !grid_box_.empty() &&
      now.lo.y < grid_box_.lo.y - Real(0.01) * grid_box_.diagonal()) {
    grid_box_.lo.y = now.lo.y - Real(0.05) * grid_box_.diagonal();
    gl_->grid = floor_grid(grid_box_);
    gl_->grid_vertices = static_cast<GLsizei>(gl_->grid.size() / 6);
    upload_lines();
  }
}

void Renderer::upload_positions() {
  Gl& g = *gl_;
  scratch_xyz_.resize(positions_.size() * 3);
  for (std::size_t i = 0; i < positions_.size(); ++i) {
    scratch_xyz_[3 * i] = float(positions_[i].x);
    scratch_xyz_[3 * i + 1] = float(positions_[i].y);
    scratch_xyz_[3 * i + 2] = float(positions_[i].z);
  }
  if (!scratch_xyz_.empty())
    glNamedBufferSubData(g.positions, 0, GLsizeiptr(scratch_xyz_.size() * 4), scratch_xyz_.data());
  positions_changed();
}

unsigned Renderer::drawn_positions() const {
  return device_positions_ != 0 ? device_positions_ : gl_->positions;
}

void Renderer::positions_changed() {
  Gl& g = *gl_;
  const GLuint positions = drawn_positions();
  // Bound again on every change: a buffer written in another context of the share group is
  // seen here once it is bound again after the writer's fence (the exchange waited on it).
  glVertexArrayVertexBuffer(g.surface_vao, 0, positions, 0, 12);
  const auto n = static_cast<GLuint>(positions_.size());
  if (g.triangle_indices > 0 && n > 0) {
    glUseProgram(g.normals_pass);
    glProgramUniform1ui(g.normals_pass, glGetUniformLocation(g.normals_pass, "u_points"), n);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 0, positions);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 1, g.normals);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 2, g.triangles);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 3, g.face_offset);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 4, g.faces_of);
    glDispatchCompute((n + 63) / 64, 1, 1);
    glMemoryBarrier(GL_VERTEX_ATTRIB_ARRAY_BARRIER_BIT | GL_SHADER_STORAGE_BARRIER_BIT |
                    GL_BUFFER_UPDATE_BARRIER_BIT);
  }
  if (g.contact_total > 0 && n > 0) {
    const std::uint32_t empty[4] = {0, 1, 0, 0};
    glNamedBufferSubData(g.contacts_command, 0, sizeof empty, empty);
    glUseProgram(g.contacts_pass);
    glProgramUniform1ui(g.contacts_pass, glGetUniformLocation(g.contacts_pass, "u_links"),
                        GLuint(g.contact_total));
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 0, positions);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 1, g.contact_ends);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 2, g.contact_threshold);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 3, g.contacts_active);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 4, g.contacts_command);
    glDispatchCompute((GLuint(g.contact_total) + 63) / 64, 1, 1);
    glMemoryBarrier(GL_COMMAND_BARRIER_BIT | GL_SHADER_STORAGE_BARRIER_BIT);
  }
  // A device's box: one reduction at a time, read when done (poll_device_bounds).
  if (device_positions_ != 0 && n > 0 && !g.box_ready) {
    glUseProgram(g.bounds_pass);
    glProgramUniform1ui(g.bounds_pass, glGetUniformLocation(g.bounds_pass, "u_points"), n);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 0, positions);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 1, g.box);
    glDispatchCompute(1, 1, 1);
    glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
    g.box_ready = glFenceSync(GL_SYNC_GPU_COMMANDS_COMPLETE, 0);
  }
  glUseProgram(0);
}

void Renderer::poll_device_bounds() {
  Gl& g = *gl_;
  if (!g.box_ready) return;
  if (glClientWaitSync(g.box_ready, GL_SYNC_FLUSH_COMMANDS_BIT, 0) == GL_TIMEOUT_EXPIRED) return;
  glDeleteSync(g.box_ready);
  g.box_ready = nullptr;
  float box[8];
  glGetNamedBufferSubData(g.box, 0, sizeof box, box);
  device_bounds_ = {};
  if (box[3] > 0) {
    device_bounds_.add(Vec3{box[0], box[1], box[2]});
    device_bounds_.add(Vec3{box[4], box[5], box[6]});
  }
  if (device_positions_ != 0) lower_grid(device_bounds_);
}

void Renderer::wait_for_bounds() {
  Gl& g = *gl_;
  if (!g.box_ready) return;
  constexpr GLuint64 kSecond = 1000000000;
  while (glClientWaitSync(g.box_ready, GL_SYNC_FLUSH_COMMANDS_BIT, kSecond) == GL_TIMEOUT_EXPIRED) {
  }
  poll_device_bounds();
}

std::vector<float> Renderer::normals() const {
  std::vector<float> out(positions_.size() * 3);
  if (!out.empty())
    glGetNamedBufferSubData(gl_->normals, 0, GLsizeiptr(out.size() * 4), out.data());
  return out;
}

void Renderer::upload_solids() {
  Gl& g = *gl_;
  // Free the meshes this snapshot no longer holds (a stage removed, a method switched, a reload).
  std::erase_if(g.solids, [&](Gl::Solid& solid) {
    const bool held = std::any_of(solids_.begin(), solids_.end(),
                                  [&](const SurfaceInstance& s) { return s.mesh == solid.mesh; });
    if (!held) Gl::free(solid);
    return !held;
  });
  // Upload the new ones, once per pointer: the mesh never changes while a stage holds it.
  for (const SurfaceInstance& s : solids_) {
    if (!s.mesh || g.find(s.mesh.get())) continue;
    Gl::Solid solid;
    solid.mesh = s.mesh;
    solid.box = bounds_of(s.mesh->vertices);
    solid.closed = s.mesh->closed();
    const std::vector<float> vertices = solid_vertices(*s.mesh);
    solid.count = static_cast<GLsizei>(vertices.size() / 6);
    solid.vertices = make_buffer(vertices);
    glCreateVertexArrays(1, &solid.vao);
    for (GLuint attrib : {0u, 1u}) {
      glEnableVertexArrayAttrib(solid.vao, attrib);
      glVertexArrayAttribFormat(solid.vao, attrib, 3, GL_FLOAT, GL_FALSE, attrib * 3 * 4);
      glVertexArrayAttribBinding(solid.vao, attrib, 0);
    }
    glVertexArrayVertexBuffer(solid.vao, 0, solid.vertices, 0, 24);
    g.solids.push_back(std::move(solid));
  }
}

std::size_t Renderer::solid_meshes() const {
  return gl_->solids.size();
}

Bounds Renderer::bounds() const {
  Bounds b = device_positions_ != 0 ? device_bounds_ : bounds_of(positions_);
  for (const SurfaceInstance& s : solids_)
    if (const Gl::Solid* solid = gl_->find(s.mesh.get()); solid && solid->closed)
      b.add(placed_box(solid->box, s));
  return b;
}

void Renderer::set_overlay(std::span<const OverlaySegment> segments) {
  overlay_.assign(segments.begin(), segments.end());
  upload_lines();
}

void Renderer::upload_lines() {
  Gl& g = *gl_;
  std::vector<float> v = g.grid;
  for (const auto& s : overlay_)
    for (const Vec3& p : {s.a, s.b})
      v.insert(v.end(),
               {float(p.x), float(p.y), float(p.z), s.colour[0], s.colour[1], s.colour[2]});
  g.overlay_vertices = static_cast<GLsizei>(v.size() / 6) - g.grid_vertices;
  if (v.empty()) v.assign(6, 0.0f);
  glNamedBufferData(g.line_vertices, GLsizeiptr(v.size() * 4), v.data(), GL_DYNAMIC_DRAW);
  glVertexArrayVertexBuffer(g.lines_vao, 0, g.line_vertices, 0, 24);
}

void Renderer::draw(const Camera& camera, int width, int height, const RenderOptions& o) {
  Gl& g = *gl_;
  const double aspect = double(width) / std::max(1, height);
  const Mat4 proj = camera.projection(aspect), view = camera.view();
  const Mat4 view_proj = proj * view;

  poll_device_bounds();
  const GLuint positions = drawn_positions();
  glViewport(0, 0, width, height);
  glDisable(GL_BLEND);
  glDisable(GL_CULL_FACE);
  glDisable(GL_SCISSOR_TEST);
  glEnable(GL_PROGRAM_POINT_SIZE);
  glDepthMask(GL_TRUE);
  glClear(GL_DEPTH_BUFFER_BIT);

  // Background: depth test off, so it needs no clear of the colour buffer.
  glDisable(GL_DEPTH_TEST);
  glUseProgram(g.background);
  glBindVertexArray(g.empty_vao);
  glDrawArrays(GL_TRIANGLES, 0, 3);
  glEnable(GL_DEPTH_TEST);
  glDepthFunc(GL_LESS);

  if (o.grid && g.grid_vertices > 0) {
    glUseProgram(g.lines);
    set_uniform(g.lines, "u_view_proj", view_proj);
    glBindVertexArray(g.lines_vao);
    glDrawArrays(GL_LINES, 0, g.grid_vertices);
  }

  const int lod = std::clamp(o.smooth_lod, 1, kMaxSmoothLod);
  if (o.surface && o.smooth && !smooth_.empty()) {
    draw_smooth(view_proj, view, lod);
  } else if (o.surface && g.triangle_indices > 0) {
    draw_cloth(g.surface, view_proj, view, g.surface_vao, g.triangle_indices);
  }

  glBindVertexArray(g.empty_vao);
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 0, positions);
  glUseProgram(g.links);
  set_uniform(g.links, "u_view_proj", view_proj);
  glProgramUniform2f(g.links, glGetUniformLocation(g.links, "u_viewport"), float(width),
                     float(height));
  glProgramUniform1f(g.links, glGetUniformLocation(g.links, "u_width"), o.link_width);
  glProgramUniform1f(g.links, glGetUniformLocation(g.links, "u_strain_range"),
                     std::max(o.strain_range, 1e-6f));
  const GLint first = glGetUniformLocation(g.links, "u_first");
  const GLint strain = glGetUniformLocation(g.links, "u_strain");
  const GLint colour = glGetUniformLocation(g.links, "u_colour");
  if (o.links) {
    // Without the surface, a cloth's mesh is all there is to see: draw it.
    const bool inner = o.links_on_surface || !o.surface;
    const GLint count = inner ? g.links_total : g.links_off_surface;
    if (count > 0) {
      glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 1, g.link_ends);
      glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 2, g.link_rest);
      glProgramUniform1i(g.links, first, 0);
      glProgramUniform1i(g.links, strain, 1);
      glDrawArrays(GL_TRIANGLES, 0, count * 6);
    }
  }
  if (o.contacts && g.contact_total > 0) {
    // The active ones, as the contacts pass left them: their count is on the GPU.
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 1, g.contacts_active);
    glProgramUniform1i(g.links, first, 0);
    glProgramUniform1i(g.links, strain, 0);
    glProgramUniform3f(g.links, colour, 0.95f, 0.85f, 0.10f);
    glBindBuffer(GL_DRAW_INDIRECT_BUFFER, g.contacts_command);
    glDrawArraysIndirect(GL_TRIANGLES, nullptr);
    glBindBuffer(GL_DRAW_INDIRECT_BUFFER, 0);
  }

  if (o.points && !positions_.empty()) {
    glUseProgram(g.points);
    set_uniform(g.points, "u_view_proj", view_proj);
    glProgramUniform1f(g.points, glGetUniformLocation(g.points, "u_pixels_per_metre"),
                       proj(1, 1) * float(height) / 2);
    glProgramUniform1f(g.points, glGetUniformLocation(g.points, "u_radius"),
                       topology_.point_radius * o.point_scale);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 3, g.styles);
    glDrawArrays(GL_POINTS, 0, static_cast<GLsizei>(positions_.size()));
  }

  if (o.solids && !solids_.empty()) draw_solids(camera, view_proj, view);

  if (g.overlay_vertices > 0) {
    glDisable(GL_DEPTH_TEST);
    glUseProgram(g.lines);
    set_uniform(g.lines, "u_view_proj", view_proj);
    glBindVertexArray(g.lines_vao);
    glDrawArrays(GL_LINES, g.grid_vertices, g.overlay_vertices);
    glEnable(GL_DEPTH_TEST);
  }
  glBindVertexArray(0);
  glUseProgram(0);
}

// Translucent solids over the opaque scene. Blending depends on order, so the order is fixed:
// solids far to near (by their centres along the view axis), and within each its back faces
// (the inside, far wall) before its front faces. The depth test against the opaque scene stays
// on; depth writes are off, so one translucent layer never hides another. Sorting by centre is
// exact for solids apart and for one convex solid; interpenetrating ones may blend out of order.
void Renderer::draw_solids(const Camera& camera, const Mat4& view_proj, const Mat4& view) {
  Gl& g = *gl_;
  struct Item {
    const SurfaceInstance* instance;
    const Gl::Solid* solid;
    double depth;
  };
  std::vector<Item> items;
  const Vec3 eye = camera.eye(), forward = camera.forward();
  for (const SurfaceInstance& s : solids_) {
    const Gl::Solid* solid = g.find(s.mesh.get());
    if (!solid || solid->count == 0) continue;
    const Vec3 centre = s.direct * solid->box.centre() + s.translation;
    items.push_back({&s, solid, double(dot(centre - eye, forward))});
  }
  std::sort(items.begin(), items.end(),
            [](const Item& a, const Item& b) { return a.depth > b.depth; });

  glUseProgram(g.solid);
  set_uniform(g.solid, "u_view_proj", view_proj);
  set_uniform(g.solid, "u_view", view);
  const GLint model_at = glGetUniformLocation(g.solid, "u_model");
  const GLint normal_at = glGetUniformLocation(g.solid, "u_normal");
  const GLint colour_at = glGetUniformLocation(g.solid, "u_colour");
  glEnable(GL_BLEND);
  glBlendFunc(GL_SRC_ALPHA, GL_ONE_MINUS_SRC_ALPHA);
  glDepthMask(GL_FALSE);
  glEnable(GL_CULL_FACE);
  // Pushed back further than the cloth: a cloth lying on a solid stays in front of it.
  glEnable(GL_POLYGON_OFFSET_FILL);
  glPolygonOffset(2.0f, 2.0f);
  for (const Item& item : items) {
    const SurfaceInstance& s = *item.instance;
    const Real det = determinant(s.direct);
    if (!(std::abs(det) > 0) || !std::isfinite(det) || !is_finite(s.translation)) continue;
    Mat4 model = Mat4::identity();
    // Normals through the inverse transpose of `direct`: its cofactor matrix over det.
    std::array<float, 9> normal{};  // column-major, like the shader's mat3
    const auto& m = s.direct.m;
    for (int r = 0; r < 3; ++r) {
      for (int c = 0; c < 3; ++c) {
        model(r, c) = float(m[r][c]);
        const int r1 = (r + 1) % 3, r2 = (r + 2) % 3, c1 = (c + 1) % 3, c2 = (c + 2) % 3;
        const Real cofactor = m[r1][c1] * m[r2][c2] - m[r1][c2] * m[r2][c1];
        normal[static_cast<std::size_t>(c * 3 + r)] = float(cofactor / det);
      }
      model(r, 3) = float(s.translation[r]);
    }
    glProgramUniformMatrix4fv(g.solid, model_at, 1, GL_FALSE, model.m.data());
    glProgramUniformMatrix3fv(g.solid, normal_at, 1, GL_FALSE, normal.data());
    glProgramUniform4f(g.solid, colour_at, s.colour[0], s.colour[1], s.colour[2], s.colour[3]);
    // A mirroring placement (det < 0) turns counter-clockwise faces clockwise on screen.
    glFrontFace(det > 0 ? GL_CCW : GL_CW);
    glBindVertexArray(item.solid->vao);
    glCullFace(GL_FRONT);
    glDrawArrays(GL_TRIANGLES, 0, item.solid->count);
    glCullFace(GL_BACK);
    glDrawArrays(GL_TRIANGLES, 0, item.solid->count);
  }
  glDisable(GL_POLYGON_OFFSET_FILL);
  glFrontFace(GL_CCW);
  glDisable(GL_CULL_FACE);
  glDepthMask(GL_TRUE);
  glDisable(GL_BLEND);
}

void Renderer::prepare_smooth(int lod) {
  Gl& g = *gl_;
  if (g.smooth_lod == lod) return;
  g.delete_smooth();
  std::vector<std::uint32_t> grids;  // the shader's Grid: 4 words each
  for (const SmoothSurface::Grid& gr : smooth_.grids_at(lod))
    grids.insert(grids.end(), {gr.first, gr.nx, gr.ny, gr.vertex_offset});
  g.smooth_grids = make_buffer(grids);
  g.smooth_tris = make_buffer(smooth_.other_triangles());
  g.smooth_vertex_count = smooth_.vertex_count(lod);
  g.smooth_grid_vertices = smooth_.grid_vertices(lod);
  g.smooth_vertices = make_buffer(std::vector<float>(std::size_t(g.smooth_vertex_count) * 6));
  const std::vector<std::uint32_t> triangles = smooth_.triangles(lod);
  g.smooth_indices = make_buffer(triangles);
  g.smooth_index_count = static_cast<GLsizei>(triangles.size());
  glVertexArrayVertexBuffer(g.smooth_vao, 0, g.smooth_vertices, 0, 24);
  glVertexArrayElementBuffer(g.smooth_vao, g.smooth_indices);
  g.smooth_lod = lod;
}

void Renderer::draw_smooth(const Mat4& view_proj, const Mat4& view, int lod) {
  Gl& g = *gl_;
  prepare_smooth(lod);
  // Evaluate: one invocation per smooth vertex, from the buffers the flat pass draws from.
  glUseProgram(g.smooth);
  glProgramUniform1i(g.smooth, glGetUniformLocation(g.smooth, "u_lod"), lod);
  glProgramUniform1i(g.smooth, glGetUniformLocation(g.smooth, "u_grid_count"),
                     static_cast<GLint>(smooth_.grids().size()));
  glProgramUniform1ui(g.smooth, glGetUniformLocation(g.smooth, "u_grid_vertices"),
                      g.smooth_grid_vertices);
  glProgramUniform1ui(g.smooth, glGetUniformLocation(g.smooth, "u_total"), g.smooth_vertex_count);
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 0, drawn_positions());
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 1, g.normals);
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 2, g.smooth_grids);
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 3, g.smooth_tris);
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 4, g.smooth_vertices);
  glDispatchCompute((g.smooth_vertex_count + 63) / 64, 1, 1);
  glMemoryBarrier(GL_VERTEX_ATTRIB_ARRAY_BARRIER_BIT | GL_BUFFER_UPDATE_BARRIER_BIT);
  // Drawn as the flat surface is (same program and lighting).
  draw_cloth(g.surface, view_proj, view, g.smooth_vao, g.smooth_index_count);
}

std::vector<float> Renderer::smooth_vertices() const {
  const Gl& g = *gl_;
  std::vector<float> out;
  if (g.smooth_lod == 0) return out;
  out.resize(std::size_t(g.smooth_vertex_count) * 6);
  if (!out.empty())
    glGetNamedBufferSubData(g.smooth_vertices, 0, GLsizeiptr(out.size() * 4), out.data());
  return out;
}

}  // namespace maille::render
