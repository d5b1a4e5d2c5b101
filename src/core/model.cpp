#include "maille/model.hpp"

#include <array>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <string>
#include <vector>

#include "maille/detail/csr.hpp"
#include "maille/limits.hpp"

namespace maille {

std::string check_model(const Model& m) {
  const std::uint64_t n = m.points.size();
  for (const auto& pool : m.links.pools())
    for (const LinkEnds& e : pool->slot_ends())
      if (e.a >= n || e.b >= n)
        return "a " + std::string(pool->keyword()) + " link joins points " + std::to_string(e.a) +
               " and " + std::to_string(e.b) + ", but the model has " + std::to_string(n) +
               " points";
  for (std::size_t f = 0; f < m.surface.triangles.size(); ++f)
    for (const std::uint32_t c : m.surface.triangles[f])
      if (c >= n)
        return "face " + std::to_string(f) + " has corner " + std::to_string(c) +
               ", but the model has " + std::to_string(n) + " points";
  for (const Drive& d : m.drives) {
    if (d.point >= n)
      return "a drive moves point " + std::to_string(d.point) + ", but the model has " +
             std::to_string(n) + " points";
    if (m.points.kind[d.point] != PointKind::driven)
      return "a drive moves point " + std::to_string(d.point) + ", which is not a driven point";
  }
  for (const Group& g : m.groups)
    if (std::uint64_t(g.first) + g.count > n)
      return "group '" + g.name + "' spans points " + std::to_string(g.first) + ".." +
             std::to_string(std::uint64_t(g.first) + g.count - 1) + ", but the model has " +
             std::to_string(n) + " points";
  return check_parameters(m);
}

namespace {

std::string number(Real v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.6g", double(v));
  return buf;
}

}  // namespace

// The scene reader's bounds (limits.hpp), applied to a model built or edited in code: a value
// the reader would refuse must not reach the step through an edit either.
std::string check_parameters(const Model& m) {
  const PointPool& p = m.points;
  for (std::uint32_t i = 0; i < p.size(); ++i) {
    if (!(p.mass[i] >= limits::min_mass && p.mass[i] <= limits::max_mass))
      return "point " + std::to_string(i) + " has mass " + number(p.mass[i]) +
             " kg, outside [1e-12, 1e12] kg";
    const Real inv = p.kind[i] == PointKind::free ? Real(1) / p.mass[i] : Real(0);
    if (p.inv_mass[i] != inv)  // mass edited without its inverse: the step would use the old one
      return "point " + std::to_string(i) + " has inv_mass " + number(p.inv_mass[i]) +
             " for mass " + number(p.mass[i]) + " kg (set both, or use PointPool::set_kind)";
    for (const Vec3& v : {p.initial_position[i], p.initial_velocity[i]})
      for (const Real c : {v.x, v.y, v.z})
        if (!(std::abs(c) <= limits::max_coordinate))
          return "point " + std::to_string(i) + " has an initial position or velocity component " +
                 number(c) + ", beyond 1e6";
  }
  for (const auto& pool : m.links.pools()) {
    const std::vector<ParamInfo> fields = pool->fields();
    for (std::size_t f = 0; f < fields.size(); ++f) {
      const Real most = limits::max_parameter(fields[f].unit);
      const Real least = fields[f].bound == Bound::any ? -most : 0;
      for (std::size_t id = 0; id < pool->size(); ++id)
        if (const Real v = pool->param(id, f); !(v >= least && v <= most))
          return "a " + std::string(pool->keyword()) + " link (" + std::to_string(id) + ") has " +
                 fields[f].name + " = " + number(v) + ", outside [" + number(least) + ", " +
                 number(most) + "] " + fields[f].unit;
    }
  }
  return {};
}

// Grid groups (Group::grid_nx, grid_ny) whose cells carry exactly the flag builder's two faces
// become FaceGrids; each face is claimed by at most one grid, and a group missing any face keeps
// all its faces out of the grids.
std::vector<FaceGrid> find_face_grids(const Model& m, std::vector<char>& in_grid) {
  const auto& tris = m.surface.triangles;
  std::vector<FaceGrid> grids;
  // Faces by first corner (counting sort).
  std::vector<std::uint32_t> start, by_first;
  const std::size_t n = m.points.size();
  detail::build_rows(n, start, by_first, [&](auto&& emit) {
    for (std::uint32_t f = 0; f < tris.size(); ++f)
      if (tris[f][0] < n) emit(tris[f][0], f);
  });
  in_grid.assign(tris.size(), 0);  // 0 loose, 1 a grid's, 2 claimed by this group
  std::vector<std::uint32_t> claimed;
  auto claim = [&](std::array<std::uint32_t, 3> want) {
    for (std::uint32_t k = start[want[0]]; k < start[want[0] + 1]; ++k) {
      const std::uint32_t f = by_first[k];
      if (in_grid[f] == 0 && tris[f] == want) {
        in_grid[f] = 2;
        claimed.push_back(f);
        return true;
      }
    }
    return false;
  };
  for (const Group& g : m.groups) {
    const std::uint32_t nx = g.grid_nx, ny = g.grid_ny;
    if (nx < 2 || ny < 2 || std::uint64_t(nx) * ny != g.count || g.first + g.count > n) continue;
    claimed.clear();
    bool whole = true;
    for (std::uint32_t j = 0; whole && j + 1 < ny; ++j)
      for (std::uint32_t i = 0; whole && i + 1 < nx; ++i) {
        const std::uint32_t p = g.first + j * nx + i;
        whole = claim({p, p + 1, p + nx + 1}) && claim({p, p + nx + 1, p + nx});
      }
    for (const std::uint32_t f : claimed) in_grid[f] = whole ? 1 : 0;
    if (whole) grids.push_back({g.first, nx, ny});
  }
  return grids;
}

namespace {

// The face grids, and the other faces by colour: a subset of a colour group shares no corner
// either, so the loose faces keep the colouring.
void find_face_grids(Model& m) {
  Surface& surface = m.surface;
  std::vector<char> in_grid;
  surface.grids = find_face_grids(m, in_grid);
  surface.loose.clear();
  surface.loose_offsets.assign(1, 0);
  for (std::size_t c = 0; c + 1 < surface.colour_offsets.size(); ++c) {
    for (std::uint32_t f = surface.colour_offsets[c]; f < surface.colour_offsets[c + 1]; ++f)
      if (in_grid[f] == 0) surface.loose.push_back(f);
    if (surface.loose.size() > surface.loose_offsets.back())
      surface.loose_offsets.push_back(static_cast<std::uint32_t>(surface.loose.size()));
  }
}

}  // namespace

std::vector<PointGrid> point_grids(const Model& m) {
  std::vector<PointGrid> out;
  for (const Group& g : m.groups)
    if (g.grid_nx >= 2 && g.grid_ny >= 2 && std::uint64_t(g.grid_nx) * g.grid_ny == g.count &&
        std::uint64_t(g.first) + g.count <= m.points.size())
      out.push_back({g.first, g.grid_nx, g.grid_ny});
  return out;
}

const Group* Model::group(const std::string& name) const {
  for (const auto& g : groups)
    if (g.name == name) return &g;
  return nullptr;
}

void Model::prepare() {
  links.prepare(points.size(), structured_grids ? point_grids(*this) : std::vector<PointGrid>{});
  // Faces are coloured like links so that the wind pass scatters to corners without races.
  std::vector<std::uint32_t> idx;
  idx.reserve(surface.triangles.size() * 3);
  for (const auto& t : surface.triangles) idx.insert(idx.end(), t.begin(), t.end());
  Colouring c = colour_elements(idx, 3, points.size());
  std::vector<std::array<std::uint32_t, 3>> sorted(surface.triangles.size());
  for (std::size_t i = 0; i < c.order.size(); ++i) sorted[i] = surface.triangles[c.order[i]];
  surface.triangles = std::move(sorted);
  surface.colour_offsets = std::move(c.offsets);
  find_face_grids(*this);
}

}  // namespace maille
