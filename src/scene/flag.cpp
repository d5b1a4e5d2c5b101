// Flag: grid cloth hung on a pole. Structural links hold the weave, shear links (cell
// diagonals) keep cells from collapsing into lozenges, bending links (every other point)
// resist folding; all are spring-dampers with rest lengths taken from the built grid.
#include "build_helpers.hpp"

namespace maille {

namespace {
bool fixed_in_flag(const FlagParams& p, std::uint32_t i, std::uint32_t j) {
  switch (p.fixed) {
    case FlagFixed::pole:
      return i == 0;
    case FlagFixed::corners:
      return i == 0 && (j == 0 || j == p.ny - 1);
    case FlagFixed::top:
      return j == p.ny - 1;
    case FlagFixed::top_corners:
      return j == p.ny - 1 && (i == 0 || i == p.nx - 1);
    case FlagFixed::ends:
      return i == 0 || i == p.nx - 1;
    case FlagFixed::none:
      return false;
  }
  return false;
}
}  // namespace

Group build_flag(Model& m, const FlagParams& p, const std::string& name) {
  const build::Grid id =
      build::grid_points(m, "flag", p.origin, p.along, p.width, p.up, p.height, p.nx, p.ny, p.mass,
                         [&](std::uint32_t i, std::uint32_t j) { return fixed_in_flag(p, i, j); });
  const Real k = p.material.stiffness, z = p.material.damping;
  // Links point by point, so that a point's links sit close together in memory.
  for (std::uint32_t j = 0; j < p.ny; ++j)
    for (std::uint32_t i = 0; i < p.nx; ++i) {
      if (i + 1 < p.nx) build::link(m, id(i, j), id(i + 1, j), k, z);
      if (j + 1 < p.ny) build::link(m, id(i, j), id(i, j + 1), k, z);
      if (i + 1 < p.nx && j + 1 < p.ny) {
        build::link(m, id(i, j), id(i + 1, j + 1), p.shear_stiffness, z);
        build::link(m, id(i + 1, j), id(i, j + 1), p.shear_stiffness, z);
      }
      if (i + 2 < p.nx) build::link(m, id(i, j), id(i + 2, j), p.bending_stiffness, z);
      if (j + 2 < p.ny) build::link(m, id(i, j), id(i, j + 2), p.bending_stiffness, z);
    }
  for (std::uint32_t j = 0; j + 1 < p.ny; ++j)
    for (std::uint32_t i = 0; i + 1 < p.nx; ++i) {
      m.surface.triangles.push_back({id(i, j), id(i + 1, j), id(i + 1, j + 1)});
      m.surface.triangles.push_back({id(i, j), id(i + 1, j + 1), id(i, j + 1)});
    }
  return build::grid_group(m, name, "flag", id.first, p.nx, p.ny);
}

}  // namespace maille
