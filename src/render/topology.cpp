#include "maille/render/topology.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <optional>
#include <string>

#include "maille/render/camera.hpp"
#include "maille/smooth_surface.hpp"

namespace maille::render {

namespace {

std::optional<std::size_t> field_index(const LinkPoolBase& pool, const std::string& name) {
  const auto fields = pool.fields();
  for (std::size_t k = 0; k < fields.size(); ++k)
    if (fields[k].name == name) return k;
  return std::nullopt;
}

}  // namespace

RenderTopology make_topology(const Model& model) {
  RenderTopology t;
  const PointPool& points = model.points;
  t.point_count = points.size();

  std::vector<std::uint8_t> on_surface(points.size(), 0);
  t.triangles.reserve(model.surface.triangles.size() * 3);
  for (const auto& tri : model.surface.triangles)
    for (std::uint32_t i : tri) {
      t.triangles.push_back(i);
      on_surface[i] = 1;
    }

  t.point_style.resize(points.size());
  for (std::uint32_t i = 0; i < points.size(); ++i) {
    switch (points.kind[i]) {
      case PointKind::fixed:
        t.point_style[i] = std::uint32_t(PointStyle::fixed);
        break;
      case PointKind::driven:
        t.point_style[i] = std::uint32_t(PointStyle::driven);
        break;
      case PointKind::free:
        t.point_style[i] = std::uint32_t(on_surface[i] ? PointStyle::hidden : PointStyle::free);
        break;
    }
  }

  // The drawn point size follows the typical link length (the median), so that beads of a
  // chain touch and lattice nodes leave the links visible.
  std::vector<float> lengths;
  for (const auto& pool : model.links.pools()) {
    const auto threshold = field_index(*pool, "threshold");
    const auto rest = field_index(*pool, "rest_length");
    for (std::size_t l = 0; l < pool->size(); ++l) {
      const LinkEnds e = pool->ends(l);
      if (threshold) {
        t.contact_ends.push_back(e.a);
        t.contact_ends.push_back(e.b);
        t.contact_threshold.push_back(float(pool->param(l, *threshold)));
        continue;
      }
      const Real initial = norm(points.initial_position[e.b] - points.initial_position[e.a]);
      const Real r = rest ? pool->param(l, *rest) : initial;
      t.link_ends.push_back(e.a);
      t.link_ends.push_back(e.b);
      t.link_rest.push_back(float(std::max<Real>(r, Real(1e-9))));
      t.link_on_surface.push_back(on_surface[e.a] && on_surface[e.b] ? 1 : 0);
      if (initial > 0) lengths.push_back(float(initial));
    }
  }
  if (!lengths.empty()) {
    std::nth_element(lengths.begin(), lengths.begin() + std::ptrdiff_t(lengths.size() / 2),
                     lengths.end());
    t.point_radius = 0.22f * lengths[lengths.size() / 2];
  } else {
    const Real size = bounds_of(points.initial_position).diagonal();
    t.point_radius = size > 0 ? float(size) * 0.01f : 0.01f;
  }
  return t;
}

void active_contacts(const RenderTopology& t, std::span<const Vec3> x,
                     std::vector<std::uint32_t>& active) {
  for (std::size_t c = 0; c < t.contact_threshold.size(); ++c) {
    const std::uint32_t a = t.contact_ends[2 * c], b = t.contact_ends[2 * c + 1];
    const Real s = t.contact_threshold[c];
    if (norm2(x[b] - x[a]) < s * s) {
      active.push_back(a);
      active.push_back(b);
    }
  }
}

void surface_normals(const RenderTopology& t, std::span<const Vec3> x,
                     std::vector<float>& normals) {
  vertex_normals(t.triangles, x, normals);
}

std::vector<float> solid_vertices(const TriMesh& mesh, double crease_degrees) {
  const std::size_t n_faces = mesh.triangles.size(), n_vertices = mesh.vertices.size();
  // Face normals: the cross product's length is twice the area, so sums weight faces by area.
  std::vector<Vec3> area_normal(n_faces), unit_normal(n_faces);
  for (std::size_t f = 0; f < n_faces; ++f) {
    const auto& t = mesh.triangles[f];
    const Vec3 a = mesh.vertices[t[0]], b = mesh.vertices[t[1]], c = mesh.vertices[t[2]];
    area_normal[f] = cross(b - a, c - a);
    const Real len = norm(area_normal[f]);
    unit_normal[f] = len > 0 && std::isfinite(len) ? area_normal[f] / len : Vec3{};
  }
  // The faces around each vertex (CSR: faces_of[first[v] .. first[v + 1]]).
  std::vector<std::uint32_t> first(n_vertices + 1, 0), faces_of(3 * n_faces);
  for (const auto& t : mesh.triangles)
    for (std::uint32_t v : t) ++first[v + 1];
  for (std::size_t v = 0; v < n_vertices; ++v) first[v + 1] += first[v];
  std::vector<std::uint32_t> fill(first.begin(), first.end() - 1);
  for (std::size_t f = 0; f < n_faces; ++f)
    for (std::uint32_t v : mesh.triangles[f]) faces_of[fill[v]++] = static_cast<std::uint32_t>(f);

  // Each corner compares its face with every face around its vertex: quadratic in the fan's
  // size, so a vertex shared by very many faces (a pole of a huge fan) stays flat instead.
  constexpr std::uint32_t kMaxFan = 64;
  const Real cos_crease = Real(std::cos(crease_degrees * std::numbers::pi / 180));
  std::vector<float> out;
  out.reserve(n_faces * 18);
  for (std::size_t f = 0; f < n_faces; ++f)
    for (std::uint32_t v : mesh.triangles[f]) {
      Vec3 n = area_normal[f];
      if (first[v + 1] - first[v] <= kMaxFan) {
        n = Vec3{};
        for (std::uint32_t k = first[v]; k < first[v + 1]; ++k)
          if (dot(unit_normal[faces_of[k]], unit_normal[f]) >= cos_crease)
            n += area_normal[faces_of[k]];
      }
      const Real len = norm(n);
      n = len > 0 && std::isfinite(len) ? n / len : Vec3{};
      const Vec3 p = mesh.vertices[v];
      out.insert(out.end(),
                 {float(p.x), float(p.y), float(p.z), float(n.x), float(n.y), float(n.z)});
    }
  return out;
}

}  // namespace maille::render
