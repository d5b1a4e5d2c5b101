// Greedy colouring of point sets for lock-free parallel passes: sets of one colour share no
// point, so threads can run a colour's sets at once without atomics.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

namespace maille {

// Greedy colouring of point sets (set e holds indices[offsets[e] .. offsets[e+1])) so that no
// two sets of one colour share a point. Returns the sets in colour order and colour offsets.
struct Colouring {
  std::vector<std::uint32_t> order;    // set indices, grouped by colour
  std::vector<std::uint32_t> offsets;  // colour c spans order[offsets[c] .. offsets[c+1])
};
Colouring colour_sets(std::span<const std::uint32_t> offsets,
                      std::span<const std::uint32_t> indices, std::uint32_t point_count);
// The same into `out`, with its working arrays in `scratch`: once both have grown to the size
// needed, nothing is allocated (a stage's contact pool is coloured again every step).
struct ColouringScratch {
  std::vector<std::uint32_t> colour, pending, later;
  std::vector<std::uint64_t> used;
};
void colour_sets(std::span<const std::uint32_t> offsets, std::span<const std::uint32_t> indices,
                 std::uint32_t point_count, Colouring& out, ColouringScratch& scratch);
// The same for sets of a fixed size (triangles: arity 3).
Colouring colour_elements(std::span<const std::uint32_t> indices, int arity,
                          std::uint32_t point_count);

}  // namespace maille
