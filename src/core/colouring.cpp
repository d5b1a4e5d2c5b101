#include <algorithm>
#include <bit>
#include <cstdint>
#include <vector>

#include "maille/colouring.hpp"
#include "maille/detail/csr.hpp"

namespace maille {

// Greedy colouring, in set order: each set takes the lowest colour that none of its points has
// used yet. A per-point 64-bit mask of used colours keeps it linear; sets that find all 64
// colours of a round taken wait for the next round (fresh masks, colours 64..127, ...), so any
// topology gets a valid colouring.
void colour_sets(std::span<const std::uint32_t> offsets, std::span<const std::uint32_t> indices,
                 std::uint32_t point_count, Colouring& out, ColouringScratch& scratch) {
  const std::size_t n = offsets.empty() ? 0 : offsets.size() - 1;
  std::vector<std::uint32_t>& colour = scratch.colour;
  std::vector<std::uint32_t>& pending = scratch.pending;
  std::vector<std::uint32_t>& later = scratch.later;
  std::vector<std::uint64_t>& used = scratch.used;
  colour.assign(n, 0);
  pending.resize(n);
  for (std::size_t e = 0; e < n; ++e) pending[e] = static_cast<std::uint32_t>(e);
  std::uint32_t colours = 0;
  for (std::uint32_t base = 0; !pending.empty(); base += 64) {
    used.assign(point_count, 0);
    later.clear();
    for (std::uint32_t e : pending) {
      std::uint64_t mask = 0;
      for (std::uint32_t k = offsets[e]; k < offsets[e + 1]; ++k) mask |= used[indices[k]];
      if (~mask == 0) {
        later.push_back(e);
        continue;
      }
      const int c = std::countr_one(mask);
      for (std::uint32_t k = offsets[e]; k < offsets[e + 1]; ++k)
        used[indices[k]] |= std::uint64_t(1) << c;
      colour[e] = base + static_cast<std::uint32_t>(c);
      colours = std::max(colours, colour[e] + 1);
    }
    pending.swap(later);
  }
  // Counting sort by colour, stable within a colour (keeps memory order inside each group).
  detail::build_rows(colours, out.offsets, out.order, [&](auto&& emit) {
    for (std::size_t e = 0; e < n; ++e) emit(colour[e], e);
  });
}

Colouring colour_sets(std::span<const std::uint32_t> offsets,
                      std::span<const std::uint32_t> indices, std::uint32_t point_count) {
  Colouring out;
  ColouringScratch scratch;
  colour_sets(offsets, indices, point_count, out, scratch);
  return out;
}

Colouring colour_elements(std::span<const std::uint32_t> indices, int arity,
                          std::uint32_t point_count) {
  const std::size_t n = indices.size() / static_cast<std::size_t>(arity);
  std::vector<std::uint32_t> offsets(n + 1);
  for (std::size_t e = 0; e <= n; ++e) offsets[e] = static_cast<std::uint32_t>(e * arity);
  return colour_sets(offsets, indices, point_count);
}

}  // namespace maille
