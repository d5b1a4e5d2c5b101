#include <cmath>
#include <cstdint>

#include "stages.hpp"

namespace maille::stages {

namespace {

// f += m g - gamma m v, on free points only (fixed points would ignore it anyway).
void point_fields(const Model& m, State& s) {
  const Vec3 g = m.fields.gravity;
  const Real gamma = m.fields.air_drag;
  const Real* mass = m.points.mass.data();
  const Real* inv_mass = m.points.inv_mass.data();
  const Vec3* v = s.v().data();
  Vec3* f = s.f().data();
  const auto n = static_cast<std::int64_t>(s.size());
#pragma omp for schedule(static)
  for (std::int64_t i = 0; i < n; ++i) {
    const Real w = inv_mass[i] > 0 ? mass[i] : Real(0);
    f[i] += (g - v[i] * gamma) * w;
  }
}

// Wind pressure on each face (see WindField): faces are coloured so that no two in a group
// share a corner, and each group is split among threads.
std::uint64_t wind(const Model& m, State& s) {
  const WindField& wind = m.fields.wind;
  const auto& tris = m.surface.triangles;
  const auto& groups = m.surface.colour_offsets;
  const Real coef = Real(0.5) * wind.density * wind.drag_coefficient / Real(3);
  const Vec3* x = s.x().data();
  const Vec3* v = s.v().data();
  Vec3* f = s.f().data();
  const double t = s.time;
  std::uint64_t pushed = 0;
  for (std::size_t g = 0; g + 1 < groups.size(); ++g) {
    const auto begin = static_cast<std::int64_t>(groups[g]);
    const auto end = static_cast<std::int64_t>(groups[g + 1]);
#pragma omp for schedule(static)
    for (std::int64_t k = begin; k < end; ++k) {
      const auto [a, b, c] = tris[static_cast<std::size_t>(k)];
      const Vec3 area2 = cross(x[b] - x[a], x[c] - x[a]);  // 2 A n
      const Real len = norm(area2);
      if (len == 0) continue;
      const Vec3 n = area2 / len;
      const Vec3 centre = (x[a] + x[b] + x[c]) / Real(3);
      const Vec3 rel = wind.at(centre, t) - (v[a] + v[b] + v[c]) / Real(3);
      const Real vn = dot(rel, n);
      // F = 1/2 rho Cd A |vn| vn n, with A = len / 2, a third to each corner.
      const Vec3 fc = n * (coef * Real(0.5) * len * std::abs(vn) * vn);
      f[a] += fc;
      f[b] += fc;
      f[c] += fc;
      ++pushed;
    }
  }
  return pushed;
}

}  // namespace

std::uint64_t field_forces(const Model& m, State& s, int threads) {
  const bool with_wind = m.fields.wind.active() && !m.surface.triangles.empty();
  std::uint64_t pushed = 0;
  if (threads > 1) {
#pragma omp parallel num_threads(threads)
    {
      point_fields(m, s);
      if (with_wind) {
        const std::uint64_t mine = wind(m, s);
#pragma omp atomic
        pushed += mine;
      }
    }
  } else {
    point_fields(m, s);
    if (with_wind) pushed = wind(m, s);
  }
  return pushed;
}

}  // namespace maille::stages
