// The renderer's passes: links, points, cloth (flat and smooth), solids, overlay, floor.

#include <cmath>
#include <vector>

#include "renderer_gl.hpp"
#include "shaders.hpp"
#include "smooth_shader.hpp"

namespace maille::render {

namespace {

void set_uniform(GLuint program, const char* name, const Mat4& m) {
  glProgramUniformMatrix4fv(program, glGetUniformLocation(program, name), 1, GL_FALSE, m.m.data());
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
