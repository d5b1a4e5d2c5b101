// The GPU step's compute shaders, as sources assembled from the shared pieces: the buffer and
// record declarations of gpu_layout.hpp and the force laws of include/maille/detail/*.glsl.
#pragma once

#include <initializer_list>
#include <string>
#include <string_view>
#include <vector>

#include "gpu_layout.hpp"

namespace maille::gpu {

inline constexpr unsigned kGroupSize = 256;  // invocations per work group, every kernel

// A link kind as the forces shader calls it: its law's name in link_laws.glsl and how many
// parameters it takes after (xa, xb, va, vb).
struct KindLaw {
  std::string law;
  int fields = 0;
};

// GLSL `<type> <name>(uint kind, vec3 xa, vec3 xb, vec3 va, vec3 vb, vec4 p<extra_params>)`: the
// switch over the model's kinds, kind k calling its shared law `<law><suffix>` with its first
// `fields` parameters, then `extra_args`; `<type>(0.0)` for an unknown kind.
struct LinkSwitch {
  std::string_view type, name, suffix, extra_params, extra_args;
};
std::string link_switch_function(const std::vector<KindLaw>& kinds, const LinkSwitch& form);
// `vec3 link_force(kind, xa, xb, va, vb, p)`: each kind's force law (after the laws).
std::string link_force_function(const std::vector<KindLaw>& kinds);
// Per point: the forces of its links (a gather over its adjacency, the kind's shared law, no
// atomics), of its faces (the wind, summed from FaceForces), gravity and drag, into f. Runs the
// points u_base .. u_base + u_count - 1 (the structured layout runs the grids' points).
std::string forces_shader(const std::vector<KindLaw>& kinds);
// Per face: the wind's force on each corner (the shared pressure law and gust sines).
std::string faces_shader();
// Per point: v += kick f / m, x += drift v (free points), the health flag on non-finite values.
std::string integrate_shader();
// Per driven point: its position and velocity at t, scattered into x and v.
std::string drive_shader();

// The head of every kernel: version, work group size, the records, the buffers `used`, the
// shared laws' prelude (`real` is float) and the packed-vec3 helpers LOAD3 / STORE3.
std::string kernel_head(std::initializer_list<Buf> used);
// A kernel's source: its head for the buffers `used`, then `parts` in order (laws, generated
// functions and definitions, the body from glsl/).
std::string kernel_source(std::initializer_list<Buf> used,
                          std::initializer_list<std::string_view> parts);

// The self-collision grid (gpu_self_collision.hpp), one kernel per pass of a step:
//   bounds    per particle: the box of the colliding particles (work-group reduction, then
//             atomicMin / atomicMax on order-preserving bits)
//   grid      one invocation: origin, cell size (grown until the grid fits the cell budget),
//             dimensions; resets the box
//   zero      per cell: counts to 0
//   count     per particle: its cell (clamped to the border), its rank there (atomicAdd)
//   scan      per block of 2 x kGroupSize counts: exclusive prefix sums (Blelloch), the block's
//             total into the level above; scan_add adds the scanned totals back
//   scatter   per particle: into the sorted order at its cell's start + its rank
//   sort      per cell: its particles by index (insertion sort): the order no longer depends
//             on the atomics' order, so neither do the sums
//   contacts  per particle: the 27 cells around its own, distance, exclusion (binary search in
//             its row), the shared contact laws, added into f (a gather: no float atomics)
// Their names ("bounds", ..., "contacts") and sources, in that order.
struct KernelSource {
  std::string name, source;
};
std::vector<KernelSource> self_collision_kernels();
inline constexpr unsigned kScanBlock = 2 * kGroupSize;  // counts scanned per work group

}  // namespace maille::gpu
