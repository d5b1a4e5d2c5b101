// What an obstacle's validation needs from the methods without building their stages.
#pragma once

#include <cstdint>

#include "maille/mesh.hpp"
#include "maille/shapes.hpp"

namespace maille {

// The conditional method refuses samplings that would not fit in memory (a huge obstacle with a
// tiny threshold).
inline constexpr std::uint64_t kMaxSurfaceSamples = 20'000'000;

// An upper bound on the samples the conditional method lays on `mesh` placed by `place` at
// `spacing` (each facet's triangular lattice before shared points merge); stops counting once
// above kMaxSurfaceSamples.
std::uint64_t planned_surface_samples(const TriMesh& mesh, const shapes::Affine& place,
                                      Real spacing);

}  // namespace maille
