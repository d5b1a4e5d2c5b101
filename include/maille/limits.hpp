// Input limits: what a scene file or a command line may ask for. Values beyond them are refused
// where they are written (the scene line and key, exit 1; a command-line option, exit 2) before
// anything is allocated or simulated. docs/scene-format.md ("Limits") lists them.
#pragma once

#include <cstdint>
#include <string>
#include <string_view>

#include "maille/vec3.hpp"

namespace maille::limits {

// Physical values. Beyond these, omega^2 = k/m or positions overflow double arithmetic long
// before a simulation could mean anything.
inline constexpr Real min_mass = Real(1e-12);      // kg, any point mass or builder total
inline constexpr Real max_mass = Real(1e12);       // kg, the same: with speeds and heights
                                                   // within max_coordinate, energies stay
                                                   // below 1e30 J (1e308 gave "inf J")
inline constexpr Real max_stiffness = Real(1e12);  // N/m (and N.s/m for damping): every
                                                   // link parameter, by magnitude
inline constexpr Real max_coordinate = Real(1e6);  // m (m/s, m/s^2): every vector component
                                                   // and length in a scene

// The one bound on a link parameter or contact law value, whoever reads it ([[link]] fields,
// [[contact]], [[obstacle]], [self_collision], the Python module): a length within the scene's
// box, anything else (stiffness, damping) within max_stiffness; stiffness and damping are >= 0
// everywhere (0 is a legal, if idle, law).
inline constexpr Real max_parameter(std::string_view unit) {
  return unit == "m" ? 2 * max_coordinate : max_stiffness;
}

// Time. The total step count of a run (duration / step, or --steps) is bounded.
inline constexpr Real min_step = Real(1e-12);                  // s
inline constexpr Real max_duration = Real(1e9);                // s
inline constexpr std::uint64_t max_steps = 1'000'000'000'000;  // 1e12 steps

// Sizes. A model is refused before it is built when its estimated size exceeds either cap.
inline constexpr std::uint64_t max_points = std::uint64_t{1} << 28;
inline constexpr std::uint64_t max_links = std::uint64_t{1} << 31;
// Estimated bytes of the built model, simulator and frame writers included; links include the
// colouring and the implicit solver's blocks. Measured: a 60^3 lattice (216,000 points,
// 2.7 million links) peaks at 200 MB with leapfrog and 383 MB with implicit Euler, against an
// estimate of 640 MB.
inline constexpr std::uint64_t bytes_per_point = 400;
inline constexpr std::uint64_t bytes_per_link = 200;
inline constexpr std::uint64_t bytes_per_face = 24;
// Half the physical memory (sysconf), or half the address-space limit (ulimit -v) when lower, or
// MAILLE_MEMORY_BUDGET bytes when that is set (tests). Besides the model, it bounds the
// conditional obstacles' surface samples and the self-collision contacts.
std::uint64_t memory_budget_bytes();

// Files and threads.
inline constexpr std::uint64_t max_scene_file_bytes = std::uint64_t{64} << 20;  // 64 MiB
inline constexpr int max_threads = 1024;

// A model's size: what a builder or contact table is about to add to what exists.
struct SizeEstimate {
  std::uint64_t points = 0, links = 0, faces = 0;
  std::uint64_t bytes() const {
    return points * bytes_per_point + links * bytes_per_link + faces * bytes_per_face;
  }
};
// Empty when `total` fits; else "would make N points, M links, about B GiB (limit: ...)".
std::string check_size(const SizeEstimate& total);

}  // namespace maille::limits
