// Lattice: a 3-D block (or ball) of points, the soft-body brick of CORDIS "jelly".
// Structural links join axis neighbours; shear links join face and body diagonals, which is
// what makes the block resist shearing and volume loss. The surface is the set of outer faces
// of full cells (all 8 corners present), oriented outwards.
#include <array>
#include <stdexcept>
#include <vector>

#include "build_helpers.hpp"

namespace maille {

Group build_lattice(Model& m, const LatticeParams& p, const std::string& name) {
  // Plain variables, not a structured binding: lambdas below capture them (clang < 16 refuses).
  const std::uint32_t nx = p.resolution[0], ny = p.resolution[1], nz = p.resolution[2];
  if (nx < 2 || ny < 2 || nz < 2) throw std::invalid_argument("lattice resolution must be >= 2");
  const Vec3 step{p.size.x / Real(nx - 1), p.size.y / Real(ny - 1), p.size.z / Real(nz - 1)};
  const Vec3 centre = p.origin + p.size * Real(0.5);
  const Real radius = std::min({p.size.x, p.size.y, p.size.z}) / 2;
  auto position = [&](std::uint32_t i, std::uint32_t j, std::uint32_t k) {
    return p.origin + Vec3{Real(i) * step.x, Real(j) * step.y, Real(k) * step.z};
  };
  auto kept = [&](std::uint32_t i, std::uint32_t j, std::uint32_t k) {
    return p.shape == LatticeShape::box ||
           norm(position(i, j, k) - centre) <= radius * (1 + Real(1e-9));
  };
  std::uint32_t count = 0;
  for (std::uint32_t k = 0; k < nz; ++k)
    for (std::uint32_t j = 0; j < ny; ++j)
      for (std::uint32_t i = 0; i < nx; ++i) count += kept(i, j, k);
  if (count == 0) throw std::invalid_argument("lattice has no point");
  const Real point_mass = p.mass / Real(count);

  const std::uint32_t first = m.points.size();
  std::vector<std::int64_t> index(std::size_t(nx) * ny * nz, -1);
  auto slot = [&](std::int64_t i, std::int64_t j, std::int64_t k) -> std::int64_t {
    if (i < 0 || j < 0 || k < 0 || i >= nx || j >= ny || k >= nz) return -1;
    return index[(std::size_t(k) * ny + std::size_t(j)) * nx + std::size_t(i)];
  };
  for (std::uint32_t k = 0; k < nz; ++k)
    for (std::uint32_t j = 0; j < ny; ++j)
      for (std::uint32_t i = 0; i < nx; ++i)
        if (kept(i, j, k)) {
          const bool fixed = p.fixed == LatticeFixed::bottom && j == 0;
          index[(std::size_t(k) * ny + j) * nx + i] =
              m.points.add(fixed ? PointKind::fixed : PointKind::free, point_mass,
                           position(i, j, k), p.velocity);
        }

  // Links to the 13 "forward" neighbours among the 26 (each pair once).
  for (std::int64_t k = 0; k < nz; ++k)
    for (std::int64_t j = 0; j < ny; ++j)
      for (std::int64_t i = 0; i < nx; ++i) {
        const std::int64_t a = slot(i, j, k);
        if (a < 0) continue;
        for (int dz = 0; dz <= 1; ++dz)
          for (int dy = -1; dy <= 1; ++dy)
            for (int dx = -1; dx <= 1; ++dx) {
              const bool forward = dz > 0 || (dz == 0 && (dy > 0 || (dy == 0 && dx > 0)));
              const std::int64_t b = slot(i + dx, j + dy, k + dz);
              if (!forward || b < 0) continue;
              const bool axis = dx * dx + dy * dy + dz * dz == 1;
              build::link(m, static_cast<std::uint32_t>(a), static_cast<std::uint32_t>(b),
                          axis ? p.material.stiffness : p.shear_stiffness, p.material.damping);
            }
      }

  // Outer faces of full cells, counter-clockwise seen from outside.
  auto full = [&](std::int64_t i, std::int64_t j, std::int64_t k) {
    for (int c = 0; c < 8; ++c)
      if (slot(i + (c & 1), j + ((c >> 1) & 1), k + ((c >> 2) & 1)) < 0) return false;
    return true;
  };
  for (std::int64_t k = 0; k + 1 < nz; ++k)
    for (std::int64_t j = 0; j + 1 < ny; ++j)
      for (std::int64_t i = 0; i + 1 < nx; ++i) {
        if (!full(i, j, k)) continue;
        const std::array<std::int64_t, 3> cell{i, j, k};
        for (int axis = 0; axis < 3; ++axis)
          for (int side = 0; side <= 1; ++side) {
            std::array<std::int64_t, 3> next = cell;
            next[axis] += side ? 1 : -1;
            if (full(next[0], next[1], next[2])) continue;
            const int b = (axis + 1) % 3, c = (axis + 2) % 3;  // e_b x e_c = e_axis
            auto corner = [&](int ub, int uc) {
              std::array<std::int64_t, 3> q = cell;
              q[axis] += side;
              q[b] += ub;
              q[c] += uc;
              return static_cast<std::uint32_t>(slot(q[0], q[1], q[2]));
            };
            const std::uint32_t p00 = corner(0, 0), p10 = corner(1, 0), p11 = corner(1, 1),
                                p01 = corner(0, 1);
            if (side) {
              m.surface.triangles.push_back({p00, p10, p11});
              m.surface.triangles.push_back({p00, p11, p01});
            } else {
              m.surface.triangles.push_back({p00, p11, p10});
              m.surface.triangles.push_back({p00, p01, p11});
            }
          }
      }
  return build::group(m, name, "lattice", first);
}

}  // namespace maille
