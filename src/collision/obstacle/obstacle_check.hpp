// What an obstacle's validation needs from the methods without building their stages.
#pragma once

#include <cstdint>
#include <string>

#include "maille/mesh.hpp"
#include "maille/shapes.hpp"

namespace maille {

// Why the conditional method cannot sample `mesh` placed by `place` at `spacing` (empty: it can),
// decided before sampling: a threshold below the precision of the positions, or more samples
// (each facet's triangular lattice, counted in double) than kMaxSurfaceSamples or than the memory
// budget holds at kBytesPerSample each; the message gives the threshold that would fit.
inline constexpr double kMaxSurfaceSamples = 20'000'000;
inline constexpr double kBytesPerSample = 120;  // the sample, the merge table's node, the cells
std::string sampling_problem(const TriMesh& mesh, const shapes::Affine& place, Real spacing);

}  // namespace maille
