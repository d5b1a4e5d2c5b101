// The GPU backend: the step in OpenGL 4.5 compute shaders, behind the backend
// seam of backend.hpp. Headless through EGL: Mesa's llvmpipe software driver where there is no
// GPU (CI), an EGL device otherwise. Built with the renderer (MAILLE_BUILD_RENDER).
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace maille {
class Backend;
}

namespace maille::gpu {

// Registers "gpu" in BackendRegistry::global() (once: later calls do nothing). Programs call it
// first thing; the engine libraries never depend on OpenGL.
void register_backend();

// The self-collision grid as the GPU left it after the backend's last force pass (tests,
// studies): the counting sort's result and each particle's contacts.
struct SelfCollisionDebug {
  std::vector<std::uint32_t> particles;   // [n_c] global ids of the colliding points
  std::vector<std::uint32_t> contacts;    // [n_c] contacts each found (a pair counts at both)
  std::vector<std::uint32_t> cell_of;     // [n_c] each particle's cell
  std::vector<std::uint32_t> cell_start;  // [cells + 1] where each cell starts in `order`
  std::vector<std::uint32_t> order;       // [n_c] local indices sorted by cell, then index
  std::array<float, 3> origin{};          // m, the grid's corner (the box's lower corner)
  float cell = 0;                         // m, the cell size used
  std::array<std::uint32_t, 3> dims{};    // cells along x, y, z
  std::uint32_t budget = 0;               // cells at most (cell_start has budget + 1 entries)
};
// The first self-collision stage's grid on a "gpu" backend; nullopt for another backend or when
// it runs no self-collision. Waits for the device.
std::optional<SelfCollisionDebug> self_collision_debug(Backend& b);

// How the GPU runs the links of grid cloth (the grids the CPU's structured kernel takes,
// detail/structured_grid.hpp; docs/gpu.md, "The structured layout"):
//   automatic   structured on the grids where it pays (at least kStructuredMinPoints points),
//               general elsewhere
//   structured  structured on every grid the CPU takes
//   general     every link through the per-point adjacency
// The environment variable MAILLE_GPU_LAYOUT = auto | structured | general chooses it for every
// gpu backend the process starts (benchmarks, tests); unset: automatic. Another value is refused
// when the backend starts, naming the variable.
enum class GridLayout : std::uint8_t { automatic, structured, general };
inline constexpr std::uint32_t kStructuredMinPoints = 4096;  // 64 x 64

// A grid the backend's last load runs structured: its first point and its size.
struct StructuredGridInfo {
  std::uint32_t first = 0, nx = 0, ny = 0;
};
// The layout a "gpu" backend runs with, and the grids it ran structured at its last load (empty
// for another backend, the general layout, or a model without grids).
GridLayout grid_layout(Backend& b);
std::vector<StructuredGridInfo> structured_grids(Backend& b);

}  // namespace maille::gpu
