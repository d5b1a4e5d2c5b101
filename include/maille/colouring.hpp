// Greedy colourings for lock-free parallel passes: sets of one colour share no point, so
// threads can run a colour's sets at once without atomics; points of one colour are not
// neighbours, so a colour's points can be updated at once (vertex block descent's sweeps).
#pragma once

#include <cstdint>
#include <limits>
#include <span>
#include <vector>

namespace maille {

inline constexpr std::uint32_t kUncoloured = std::numeric_limits<std::uint32_t>::max();

// Greedy colouring of points: in the order of `points`, each takes the smallest colour none of
// its coloured neighbours holds. `neighbours(i, visit)` calls visit(j) for every neighbour j of
// i (repeats allowed). colour[] must hold kUncoloured for every point on entry; points left
// out of `points` stay uncoloured and constrain nothing (fixed points). `stamp` is working
// memory, its capacity kept. Returns the number of colours.
template <class Points, class Neighbours>
std::uint32_t colour_points(const Points& points, std::vector<std::uint32_t>& colour,
                            std::vector<std::uint32_t>& stamp, Neighbours&& neighbours) {
  std::uint32_t colours = 0;
  for (const std::uint32_t i : points) {
    neighbours(i, [&](std::uint32_t j) {
      if (colour[j] != kUncoloured) stamp[colour[j]] = i;  // colour[j] is taken around i
    });
    std::uint32_t c = 0;
    while (c < colours && stamp[c] == i) ++c;
    if (c == colours) {  // a new colour: its stamp may be a former call's
      ++colours;
      if (stamp.size() < colours) stamp.push_back(kUncoloured);
      stamp[c] = kUncoloured;
    }
    colour[i] = c;
  }
  return colours;
}

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
