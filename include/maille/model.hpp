// The model: everything built once from a scene (or by code) and constant during a run
// (the viewer edits parameters only between steps).
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "maille/drive.hpp"
#include "maille/fields.hpp"
#include "maille/geometric_point.hpp"
#include "maille/link_set.hpp"
#include "maille/points.hpp"
#include "maille/stage.hpp"

namespace maille {

// A regular grid of faces, as the flag builder lays them out: points first + j nx + i for
// i < nx, j < ny, and in each cell (i, j) < (nx - 1, ny - 1), with p = first + j nx + i, the two
// faces (p, p + 1, p + nx + 1) and (p, p + nx + 1, p + nx). The wind stage runs such faces row by
// row with contiguous loads, each point summing the forces of its six faces (field_forces.cpp).
struct FaceGrid {
  std::uint32_t first = 0;       // point index of (0, 0)
  std::uint32_t nx = 0, ny = 0;  // points per row, rows (>= 2 each)
};

// Cloth faces: wind acts on them; renderers and frame writers draw them.
struct Surface {
  std::vector<std::array<std::uint32_t, 3>> triangles;  // point indices, counter-clockwise
  // Filled by Model::prepare():
  std::vector<std::uint32_t> colour_offsets;  // triangles by colour (no shared corner in one)
  std::vector<FaceGrid> grids;                // grid groups whose faces are all in triangles
  std::vector<std::uint32_t> loose;           // the other faces (indices into triangles), by colour
  std::vector<std::uint32_t> loose_offsets;   // colour c spans loose[loose_offsets[c] .. [c+1])
};

// A named range of points made by one builder or one explicit declaration.
struct Group {
  std::string name;
  std::string builder;  // "flag", "rope", ..., or "points" for explicit bricks
  std::uint32_t first = 0;
  std::uint32_t count = 0;
  // Grid builders (flag, net) lay points out row-major: point first + j * grid_nx + i is (i, j).
  // 0: not a grid. Self-collision uses it for topological signatures.
  std::uint32_t grid_nx = 0, grid_ny = 0;
};

struct Model {
  PointPool points;
  LinkSet links;
  Fields fields;
  Surface surface;
  std::vector<Drive> drives;
  std::vector<Group> groups;
  // Geometric fixed points ([[geometric_point]]): shapes with no velocity or force, reached
  // only through geometric contact links (geometric_point.hpp).
  std::vector<GeometricPoint> geometric_points;
  // Stages the scene installed ([self_collision], [[obstacle]], ...): every Simulator built from
  // this model instantiates them (see stage_registry.hpp).
  std::vector<StageSpec> stages;
  // A hash of the scene this model was read from, every key after --set overrides but those
  // that only choose outputs (src/scene/scene_digest.cpp); 0 for a model built in code. The
  // checkpoint fingerprint includes it, so no trajectory-changing key can be left out of it.
  std::uint64_t scene_digest = 0;
  // Links of kinds that opt in (spring-dampers) on the grid groups run in the structured kernel
  // (detail/structured_grid.hpp); false: every link on the general schedule, to compare the
  // two paths (tests, benchmarks). The same forces up to the order of each point's sum.
  bool structured_grids = true;

  const Group* group(const std::string& name) const;
  // Groups links and faces for parallel, deterministic force passes. Call once after building
  // (the simulator does it); building more afterwards requires calling it again.
  void prepare();
};

// Why `m` is not a model a simulator can run (empty: it is): every link's ends, every face's
// corners, every drive's point and every group's range inside the points, drives on driven
// points. The simulator checks models when it is built and after each edit_model.
// It also runs check_parameters.
std::string check_model(const Model& m);
// Why m's values are not ones a scene could give (empty: they are): point masses in
// [1e-12, 1e12] kg with inv_mass their inverse (0 for fixed and driven points), initial
// positions and velocities within 1e6, every link parameter finite and within its field's bound
// and limits::max_parameter. Run by check_model.
std::string check_parameters(const Model& m);

// The face grids of m's surface (see FaceGrid) whatever the triangles' order; in_grid[f] is 1
// for the triangles they hold, 0 for the others. Model::prepare keeps them in Surface::grids;
// the smooth surface (smooth_surface.hpp) asks for them of models not prepared.
std::vector<FaceGrid> find_face_grids(const Model& m, std::vector<char>& in_grid);

// The point grids of m's grid groups (Group::grid_nx, grid_ny): flags, nets, cloths, with or
// without faces. Model::prepare runs the links on them in the structured kernel
// (detail/structured_grid.hpp).
std::vector<PointGrid> point_grids(const Model& m);

}  // namespace maille
