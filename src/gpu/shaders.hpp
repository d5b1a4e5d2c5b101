// The GPU step's compute shaders, as sources assembled from the shared pieces: the buffer and
// record declarations of gpu_layout.hpp and the force laws of include/maille/detail/*.glsl.
#pragma once

#include <string>
#include <string_view>
#include <vector>

namespace maille::gpu {

inline constexpr unsigned kGroupSize = 256;  // invocations per work group, every kernel

// A link kind as the forces shader calls it: its law's name in link_laws.glsl and how many
// parameters it takes after (xa, xb, va, vb).
struct KindLaw {
  std::string law;
  int fields = 0;
};

// Per point: the forces of its links (a gather over its adjacency, the kind's shared law, no
// atomics), of its faces (the wind, summed from FaceForces), gravity and drag, into f.
std::string forces_shader(const std::vector<KindLaw>& kinds);
// Per face: the wind's force on each corner (the shared pressure law and gust sines).
std::string faces_shader();
// Per point: v += kick f / m, x += drift v (free points), the health flag on non-finite values.
std::string integrate_shader();
// Per driven point: its position and velocity at t, scattered into x and v.
std::string drive_shader();

}  // namespace maille::gpu
