// The GPU backend (Theme 3, T3.2): the step in OpenGL 4.5 compute shaders, behind the backend
// seam of backend.hpp. Headless through EGL: Mesa's llvmpipe software driver where there is no
// GPU (CI), an EGL device otherwise. Built with the renderer (MAILLE_BUILD_RENDER).
#pragma once

#include <string>

namespace maille::gpu {

// Registers "gpu" in BackendRegistry::global(). Programs call it once, first thing; the engine
// libraries never depend on OpenGL.
void register_backend();

// The driver, the device and the limits that matter (work groups, storage blocks), from a
// context made for the purpose, and the EGL devices present: `maille info --backend gpu`.
// Throws std::runtime_error when no OpenGL 4.5 context can be made.
std::string describe(int device = -1);

}  // namespace maille::gpu
