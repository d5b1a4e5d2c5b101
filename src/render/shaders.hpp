// GLSL 4.50 sources of the renderer's passes. Positions live in one buffer of 3 floats per
// point, bound as a shader storage buffer (binding 0) for the passes that fetch points by index
// (links, contacts, points: "vertex pulling", no per-pass copies) and as a vertex attribute for
// the surface pass.
#pragma once

#include <string_view>

#include "render_glsl.hpp"  // generated from src/render/glsl/*.glsl (cmake/EmbedGlsl.cmake)

namespace maille::render::shaders {

// Each pass's stages are src/render/glsl/<pass>_<vs|fs|cs>.glsl, of the same name here; the
// links' ribbons are coloured as plain lines.
inline constexpr std::string_view links_fs = lines_fs;

}  // namespace maille::render::shaders
