#include "maille/render/renderer.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <memory>
#include <stdexcept>
#include <string>

#include "maille/detail/csr.hpp"
#include "renderer_gl.hpp"
#include "shaders.hpp"
#include "smooth_shader.hpp"

namespace maille::render {

namespace {

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
  std::vector<std::uint32_t> face_offset, faces_of;
  detail::build_rows(positions_.size(), face_offset, faces_of, [&](auto&& emit) {
    for (std::size_t k = 0; k < topology_.triangles.size(); ++k)
      emit(topology_.triangles[k], k / 3);
  });
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
}  // namespace maille::render
