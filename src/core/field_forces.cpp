#include <algorithm>
#include <cmath>
#include <cstdint>

#include "gust.hpp"
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
// share a corner, and each group is split among threads in blocks of faces.
//
// Each block runs in three passes over small struct-of-arrays buffers on the stack:
//   1. gather (scalar): per face, the doubled area vector and the sums of corner positions and
//      velocities (indexed loads of 24-byte Vec3s do not vectorise well);
//   2. pressure (vectorised by GCC, contiguous loads only): unit normal, the gust field at the
//   centre
//      (gust.hpp, inlined and branch-free), the normal relative velocity, the force magnitude;
//   3. scatter (scalar): the force to the three corners (a vectorised loop cannot know that
//      faces of one colour share no corner).
// Per face this is the arithmetic WindField::at and the former one-loop version did, in the
// same order: results are bit-identical to them. The gust field was 80 % of the default scene's
// step before (docs/benchmarks.md).
constexpr std::int64_t wind_block = 64;

template <bool Gusty>
std::uint64_t wind(const Model& m, State& s) {
  const gust::Basis basis = gust::basis(m.fields.wind, s.time);
  const Real mean_x = basis.mean.x, mean_y = basis.mean.y, mean_z = basis.mean.z;
  const auto* tris = m.surface.triangles.data();
  const auto& groups = m.surface.colour_offsets;
  const Real coef = Real(0.5) * m.fields.wind.density * m.fields.wind.drag_coefficient / Real(3);
  const Vec3* x = s.x().data();
  const Vec3* v = s.v().data();
  Vec3* f = s.f().data();
  std::uint64_t pushed = 0;
  for (std::size_t g = 0; g + 1 < groups.size(); ++g) {
    const auto begin = static_cast<std::int64_t>(groups[g]);
    const auto end = static_cast<std::int64_t>(groups[g + 1]);
    const std::int64_t blocks = (end - begin + wind_block - 1) / wind_block;
#pragma omp for schedule(static)
    for (std::int64_t blk = 0; blk < blocks; ++blk) {
      const std::int64_t first = begin + blk * wind_block;
      const std::int64_t count = std::min(wind_block, end - first);
      // [count] each: area vector 2 A n (m^2), sum of corner positions (m) and velocities (m/s),
      // then the unit normal, 2 A and the force along the normal on each corner (N).
      alignas(64) Real ax[wind_block], ay[wind_block], az[wind_block];
      alignas(64) Real px[wind_block], py[wind_block], pz[wind_block];
      alignas(64) Real vx[wind_block], vy[wind_block], vz[wind_block];
      alignas(64) Real nx[wind_block], ny[wind_block], nz[wind_block];
      alignas(64) Real len[wind_block], force[wind_block];

      // Kept scalar on purpose: GCC would use AVX-512 gathers here, measured slower (the stage
      // took 19 instead of 16 ns per particle-step on the default scene with steady wind).
#pragma omp simd simdlen(1)
      for (std::int64_t j = 0; j < count; ++j) {
        const auto [a, b, c] = tris[first + j];
        const Vec3 area2 = cross(x[b] - x[a], x[c] - x[a]);
        const Vec3 xs = x[a] + x[b] + x[c], vs = v[a] + v[b] + v[c];
        ax[j] = area2.x, ay[j] = area2.y, az[j] = area2.z;
        px[j] = xs.x, py[j] = xs.y, pz[j] = xs.z;
        vx[j] = vs.x, vy[j] = vs.y, vz[j] = vs.z;
      }

      for (std::int64_t j = 0; j < count; ++j) {
        const Vec3 area2{ax[j], ay[j], az[j]};
        const Real l = norm(area2);
        // A degenerate face (l = 0) gets n = 0 and no force: no division by zero. Written
        // l + (l == 0), not l > 0 ? l : 1: without AVX-512 masks GCC 12 will not if-convert a
        // select feeding a division, and the loop stayed scalar (x86-64-v3, portable).
        const Vec3 n = area2 / (l + Real(l == 0));
        const Vec3 centre = Vec3{px[j], py[j], pz[j]} / Real(3);
        const Vec3 w = Gusty ? gust::at(basis, centre) : Vec3{mean_x, mean_y, mean_z};
        const Vec3 rel = w - Vec3{vx[j], vy[j], vz[j]} / Real(3);
        const Real vn = dot(rel, n);
        // F = 1/2 rho Cd A |vn| vn n, with A = l / 2, a third to each corner.
        force[j] = coef * Real(0.5) * l * std::abs(vn) * vn;
        nx[j] = n.x, ny[j] = n.y, nz[j] = n.z;
        len[j] = l;
      }

      for (std::int64_t j = 0; j < count; ++j) {
        if (len[j] == 0) continue;
        const auto [a, b, c] = tris[first + j];
        const Vec3 fc = Vec3{nx[j], ny[j], nz[j]} * force[j];
        f[a] += fc;
        f[b] += fc;
        f[c] += fc;
        ++pushed;
      }
    }
  }
  return pushed;
}

std::uint64_t wind(const Model& m, State& s) {
  return m.fields.wind.turbulence > 0 && norm(m.fields.wind.velocity) > 0 ? wind<true>(m, s)
                                                                          : wind<false>(m, s);
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
