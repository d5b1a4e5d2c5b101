// The smooth-surface compute shader: evaluates include/maille/detail/smooth_math.glsl (the math
// the CPU evaluation in src/surface/smooth_surface.cpp compiles too) at every vertex of the
// smooth mesh, straight from the positions and vertex-normal buffers the renderer already
// holds, into a vertex buffer the surface pass draws. Layout as SmoothSurface::evaluate: the
// grids' vertices first (Grid::vertex_offset), then (lod + 1)(lod + 2) / 2 per PN triangle.
#pragma once

#include <string>
#include <string_view>

#include "render_glsl.hpp"  // smooth_head, smooth_math, smooth_main

namespace maille::render::shaders {

// src/render/glsl/smooth_head.glsl, include/maille/detail/smooth_math.glsl and
// src/render/glsl/smooth_main.glsl, in that order.
inline std::string smooth_cs() {
  return std::string(smooth_head) + std::string(smooth_math) + std::string(smooth_main);
}

}  // namespace maille::render::shaders
