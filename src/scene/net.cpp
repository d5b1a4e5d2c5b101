// Net: a grid of knots joined by cords along the two grid directions only, so it has no
// shear stiffness and drapes freely; no faces (wind passes through a net). With a pretension and
// its edges fixed it is a square drum skin (the live period budget's drum, docs/sound.md).
#include "build_helpers.hpp"

namespace maille {

namespace {
bool fixed_in_net(const NetParams& p, std::uint32_t i, std::uint32_t j) {
  const bool first_i = i == 0, last_i = i + 1 == p.nx, first_j = j == 0, last_j = j + 1 == p.ny;
  switch (p.fixed) {
    case NetFixed::corners:
      return (first_i || last_i) && (first_j || last_j);
    case NetFixed::ends:
      return first_i || last_i;
    case NetFixed::edges:
      return first_i || last_i || first_j || last_j;
    case NetFixed::top:
      return last_j;
    case NetFixed::all:
      return true;
    case NetFixed::none:
      return false;
  }
  return false;
}
}  // namespace

Group build_net(Model& m, const NetParams& p, const std::string& name) {
  const build::Grid id = build::grid_points(
      m, "net", p.origin, p.along, p.width, p.across, p.depth, p.nx, p.ny, p.mass,
      [&](std::uint32_t i, std::uint32_t j) { return fixed_in_net(p, i, j); });
  for (std::uint32_t j = 0; j < p.ny; ++j)
    for (std::uint32_t i = 0; i < p.nx; ++i) {
      if (i + 1 < p.nx)
        build::link(m, id(i, j), id(i + 1, j), p.material.stiffness, p.material.damping,
                    1 - p.pretension);
      if (j + 1 < p.ny)
        build::link(m, id(i, j), id(i, j + 1), p.material.stiffness, p.material.damping,
                    1 - p.pretension);
    }
  return build::grid_group(m, name, "net", id.first, p.nx, p.ny);
}

}  // namespace maille
