// The force loops over a pool's links (maille/link_loops.hpp): the structured kernel's rows and
// the general schedule's chunks, the kind's law called per batch (a row segment, a chunk).
#include <algorithm>
#include <bit>

#include "maille/link_loops.hpp"
#include "schedule_loops.hpp"

namespace maille {
namespace {

using detail::StructuredGrid;

// Link row j of grid g (detail/structured_grid.hpp): each family's forces along the row, by the
// column of the first end, zero where there is no link. A segment's ends both advance by one,
// so positions and velocities are contiguous loads and the law's loop vectorises with no index
// array; a uniform segment reads its one record once.
void link_row(const LinkPoolBase& pool, std::size_t g, std::uint32_t j, const Vec3* x,
              const Vec3* v, Real* out) {
  const StructuredGrid& stencil = pool.stencil();
  const PointGrid& grid = stencil.grids()[g];
  const std::size_t w = stencil.width();
  const std::uint32_t row_first = grid.first + j * grid.nx;
  for (std::size_t fam = 0; fam < StructuredGrid::kFamilies.size(); ++fam) {
    // An absent family's buffers are not written: they hold zeros (cut_segments).
    if (!(stencil.families(g) >> fam & 1)) continue;
    Real* bx = out + fam * 3 * w + 2;  // column c at c + 2
    Real* by = bx + w;
    Real* bz = by + w;
    std::int64_t done = -2;  // columns before this one are written
    auto zero_to = [&](std::int64_t column) {
      for (std::int64_t c = done; c < column; ++c) bx[c] = by[c] = bz[c] = 0;
    };
    const auto [s0, s1] = stencil.row_segments(g, j, fam);
    for (std::uint32_t s = s0; s < s1; ++s) {
      const auto& seg = stencil.segment(s);
      const std::int64_t i0 = std::int64_t(seg.a) - row_first;
      zero_to(i0);
      pool.run_forces(seg.slot, seg.count, x + seg.a, x + seg.b, v + seg.a, v + seg.b,
                      stencil.uniform(s), bx + i0, by + i0, bz + i0);
      done = i0 + std::int64_t(seg.count);
    }
    zero_to(std::int64_t(grid.nx) + 2);
  }
}

// The same with two families (a net's, a flag's without shear and bending).
[[gnu::always_inline]] inline Real gathered(const Real* const (&p)[2], const Real* const (&q)[2],
                                            std::size_t i) {
  Real s = 0;
  s += p[0][i];
  s += p[1][i];
  s -= q[0][i];
  s -= q[1][i];
  return s;
}

// One coordinate of point i's sum (gather_row), written out so that the loop vectorises (inlined
// into it: a call inside the vector loop would make it scalar).
[[gnu::always_inline]] inline Real gathered(const Real* const (&p)[6], const Real* const (&q)[6],
                                            std::size_t i) {
  Real s = 0;
  s += p[0][i];
  s += p[1][i];
  s += p[2][i];
  s += p[3][i];
  s += p[4][i];
  s += p[5][i];
  s -= q[0][i];
  s -= q[1][i];
  s -= q[2][i];
  s -= q[3][i];
  s -= q[4][i];
  s -= q[5][i];
  return s;
}

template <bool kAssign, std::size_t N>
void gather(const Real* const (&p)[3][N], const Real* const (&q)[3][N], std::size_t nx, Vec3* f) {
#pragma omp simd
  for (std::size_t i = 0; i < nx; ++i) {
    const Real sx = gathered(p[0], q[0], i), sy = gathered(p[1], q[1], i),
               sz = gathered(p[2], q[2], i);
    if constexpr (kAssign) {  // by coordinate: a Vec3 copy does not vectorise here
      f[i].x = sx;
      f[i].y = sy;
      f[i].z = sz;
    } else {
      f[i].x += sx;
      f[i].y += sy;
      f[i].z += sz;
    }
  }
}

// Row j's points sum their links' forces in one fixed order: as first end (row j's buffers,
// families in order), then as second end (the buffers of rows j - dj at column i - di).
// `assign`: f = the sum (the fused step, f not cleared), else f += the sum.
// `present`: the grid's families (StructuredGrid::families); with two (a net's, a flag's
// without shear and bending) only theirs are summed: the same sums, since an absent family's
// +0 leaves a sum that starts at +0 (hence is never -0) as it is.
void gather_row(const StructuredGrid& stencil, const Real* r0, const Real* r1, const Real* r2,
                std::uint32_t nx, Vec3* f, bool assign, std::uint8_t present) {
  constexpr std::size_t families = StructuredGrid::kFamilies.size();
  static_assert(families == 6);
  const std::size_t w = stencil.width();
  const Real* rows[3] = {r0, r1, r2};
  const Real* first[3][families];
  const Real* second[3][families];
  for (std::size_t fam = 0; fam < families; ++fam) {
    const auto [di, dj] = StructuredGrid::kFamilies[fam];
    for (std::size_t c = 0; c < 3; ++c) {
      first[c][fam] = r0 + (fam * 3 + c) * w + 2;
      second[c][fam] = rows[dj] + (fam * 3 + c) * w + 2 - di;
    }
  }
  if (std::popcount(present) == 2) {
    const Real* p[3][2];
    const Real* q[3][2];
    for (std::size_t fam = 0, k = 0; fam < families; ++fam)
      if (present >> fam & 1) {
        for (std::size_t c = 0; c < 3; ++c) p[c][k] = first[c][fam], q[c][k] = second[c][fam];
        ++k;
      }
    if (assign)
      gather<true>(p, q, nx, f);
    else
      gather<false>(p, q, nx, f);
    return;
  }
  if (assign)
    gather<true>(first, second, nx, f);
  else
    gather<false>(first, second, nx, f);
}

// Forces of one chunk of links. Kinds that are always active compute all forces first (the
// law's vectorised loop: contiguous loads on runs, gathers otherwise), then scatter them;
// conditional kinds test cheaply first and compute only the few active links.
std::uint64_t run_chunk(const LinkPoolBase& pool, std::size_t c, const Vec3* x, const Vec3* v,
                        Vec3* f) {
  const detail::CpuSchedule& schedule = pool.schedule();
  const std::size_t begin = pool.schedule_base() + schedule.chunk_begin(c),
                    end = pool.schedule_base() + schedule.chunk_end(c);
  if (pool.conditional()) return pool.add_active_forces(begin, end, x, v, f);
  constexpr std::size_t kChunk = detail::CpuSchedule::kChunk;
  Real fx[kChunk], fy[kChunk], fz[kChunk];  // uninitialised on purpose: fully written
  const std::size_t n = end - begin;
  const LinkEnds* e = pool.slot_ends().data();
  if (schedule.chunk_is_run(c)) {
    const std::uint32_t a0 = e[begin].a, b0 = e[begin].b;
    pool.run_forces(begin, n, x + a0, x + b0, v + a0, v + b0, false, fx, fy, fz);
    Vec3* fa = f + a0;
    Vec3* fb = f + b0;
    for (std::size_t k = 0; k < n; ++k) fa[k] += Vec3{fx[k], fy[k], fz[k]};
    for (std::size_t k = 0; k < n; ++k) fb[k] -= Vec3{fx[k], fy[k], fz[k]};
    return 0;
  }
  pool.gathered_forces(begin, n, x, v, fx, fy, fz);
  for (std::size_t k = 0; k < n; ++k) {
    const Vec3 fa{fx[k], fy[k], fz[k]};
    f[e[begin + k].a] += fa;
    f[e[begin + k].b] -= fa;
  }
  return 0;
}

}  // namespace

// The structured kernel's strips (detail/structured_grid.hpp): each thread of the team takes a
// strip of rows of each grid, computes the link rows it shares with its neighbours (two above,
// its own last two) and calls the hook's strip before a barrier, then its rows in order: link
// row, sum, hook.
void structured_forces(const LinkPoolBase& pool, const Vec3* x, const Vec3* v, Vec3* f,
                       const StructuredGrid::RowHook* hook) {
  const StructuredGrid& stencil = pool.stencil();
  if (stencil.size() == 0) return;
  if (StructuredGrid::team_size() == 1 && stencil.reserved_threads() < 1) stencil.reserve(1);
  const int team = StructuredGrid::team_size(), t = StructuredGrid::thread_index();
  Real* mine = stencil.thread_rows(t);
  const std::size_t size = stencil.link_row_size();
  Real* ring[3] = {mine, mine + size, mine + 2 * size};
  Real* halo[2] = {mine + 3 * size, mine + 4 * size};
  Real* tail[2] = {mine + 5 * size, mine + 6 * size};
  const auto grids = stencil.grids();
  for (std::size_t g = 0; g < grids.size(); ++g) {
    const PointGrid& grid = grids[g];
    const std::int64_t strips = std::clamp<std::int64_t>(grid.ny / 4, 1, team);
    const bool works = t < strips;
    const std::int64_t r0 = std::int64_t(grid.ny) * t / strips;
    const std::int64_t r1 = std::int64_t(grid.ny) * (t + 1) / strips;
    if (works) {
      for (std::int64_t h = 0; h < 2; ++h) {
        if (r0 - 2 + h >= 0) link_row(pool, g, std::uint32_t(r0 - 2 + h), x, v, halo[h]);
        if (r1 - 2 + h >= r0) link_row(pool, g, std::uint32_t(r1 - 2 + h), x, v, tail[h]);
      }
      if (hook && hook->strip) hook->strip(hook->context, g, std::uint32_t(r0), std::uint32_t(r1));
    }
#pragma omp barrier
    if (!works) continue;
    auto buffer = [&](std::int64_t row) -> const Real* {
      if (row < 0) return stencil.zero_row();
      if (row < r0) return halo[row - (r0 - 2)];
      if (row >= r1 - 2) return tail[row - (r1 - 2)];
      return ring[row % 3];
    };
    for (std::int64_t row = r0; row < r1; ++row) {
      if (row < r1 - 2) link_row(pool, g, std::uint32_t(row), x, v, ring[row % 3]);
      const std::uint32_t first = grid.first + std::uint32_t(row) * grid.nx;
      gather_row(stencil, buffer(row), buffer(row - 1), buffer(row - 2), grid.nx, f + first,
                 hook != nullptr, stencil.families(g));
      if (hook) hook->run(hook->context, g, std::uint32_t(row));
    }
  }
#pragma omp barrier
}

void other_forces(const LinkPoolBase& pool, const Vec3* x, const Vec3* v, Vec3* f) {
  detail::for_each_chunk(pool.schedule(), [&](std::uint32_t c) { run_chunk(pool, c, x, v, f); });
}

void accumulate_forces(const LinkPoolBase& pool, const Vec3* x, const Vec3* v, Vec3* f,
                       LinkCounters& counters) {
  std::uint64_t active = 0;  // this thread's count
  structured_forces(pool, x, v, f, nullptr);
  detail::for_each_chunk(pool.schedule(),
                         [&](std::uint32_t c) { active += run_chunk(pool, c, x, v, f); });
  if (pool.conditional()) {
#pragma omp atomic
    counters.active += active;
  }
}

}  // namespace maille
