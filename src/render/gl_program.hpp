// Small OpenGL helpers shared by the renderer's passes: compiling and linking programs.
// Internal to maille_render (needs epoxy's GL declarations).
#pragma once

#include <epoxy/gl.h>

#include <string_view>

namespace maille::render {

// Compiles and links a vertex and a fragment shader; throws std::runtime_error carrying the
// pass name and the driver's log when either fails.
GLuint link_program(std::string_view pass, std::string_view vertex_source,
                    std::string_view fragment_source);
// Compiles and links a compute shader (the same errors).
GLuint link_compute_program(std::string_view pass, std::string_view compute_source);

}  // namespace maille::render
