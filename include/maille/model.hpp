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

// Cloth faces: wind acts on them; renderers and frame writers draw them.
struct Surface {
  std::vector<std::array<std::uint32_t, 3>> triangles;  // point indices, counter-clockwise
  std::vector<std::uint32_t> colour_offsets;            // filled by Model::prepare()
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

  const Group* group(const std::string& name) const;
  // Groups links and faces for parallel, deterministic force passes. Call once after building
  // (the simulator does it); building more afterwards requires calling it again.
  void prepare();
};

}  // namespace maille
