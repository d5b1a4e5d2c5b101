// The work-sharing loops over a pool's schedule (detail/cpu_schedule.hpp) and structured
// kernel (detail/structured_grid.hpp), for the solvers' sources that run links. Each is
// callable inside an OpenMP parallel region (orphaned `omp for`: the threads of the team split
// each colour) or outside one (serially, in the same order, so every point sums its terms in the
// same order whatever the thread count).
#pragma once

#include <cstdint>
#include <utility>

#include "maille/link_pool.hpp"

namespace maille::detail {

// f(chunk) over every chunk of the general schedule, colour by colour.
template <class F>
void for_each_chunk(const CpuSchedule& schedule, F&& f) {
  for (std::size_t c = 0; c < schedule.colours(); ++c) {
    const auto bands = schedule.bands_of_colour(c);
    const auto count = static_cast<std::int64_t>(bands.size());
#pragma omp for schedule(static)
    for (std::int64_t k = 0; k < count; ++k) {
      const std::uint32_t band = bands[static_cast<std::size_t>(k)];
      for (std::uint32_t chunk = schedule.first_chunk(band); chunk < schedule.end_chunk(band);
           ++chunk)
        f(chunk);
    }
  }
}

// f(segment index) over every segment of the structured kernel, block colour by block colour.
template <class F>
void for_each_segment(const StructuredGrid& grid, F&& f) {
  for (std::size_t c = 0; c < grid.colours(); ++c) {
    // No structured binding: clang 14 (the web build) refuses one inside an OpenMP loop.
    const std::pair<std::uint32_t, std::uint32_t> blocks = grid.blocks_of_colour(c);
    const auto first = std::int64_t(blocks.first), end = std::int64_t(blocks.second);
#pragma omp for schedule(static)
    for (std::int64_t k = first; k < end; ++k) {
      const std::pair<std::uint32_t, std::uint32_t> block = grid.segments_of_block(std::size_t(k));
      for (std::uint32_t s = block.first; s < block.second; ++s) f(s);
    }
  }
}

// f(begin, end) over a pool's storage slots in ranges no two threads share a point in: the
// structured kernel's segments, then the schedule's chunks.
template <class F>
void for_each_range(const LinkPoolBase& pool, F&& f) {
  const StructuredGrid& grid = pool.stencil();
  if (grid.size() > 0)
    for_each_segment(grid, [&](std::size_t s) {
      const auto& g = grid.segment(s);
      f(std::size_t(g.slot), std::size_t(g.slot) + g.count);
    });
  const std::size_t base = pool.schedule_base();
  const CpuSchedule& schedule = pool.schedule();
  for_each_chunk(schedule, [&](std::uint32_t c) {
    f(base + schedule.chunk_begin(c), base + schedule.chunk_end(c));
  });
}

}  // namespace maille::detail
