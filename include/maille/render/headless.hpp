// Rendering with no display: an OpenGL 4.5 core context through EGL on Mesa's "surfaceless"
// platform (no window system, no GPU needed: Mesa's llvmpipe software driver runs it on the CPU),
// and an offscreen framebuffer to draw into and read pixels back from.
#pragma once

#include <string>

#include "maille/render/image.hpp"

namespace maille::render {

// Creates the context and makes it current on the calling thread for its whole life.
// Throws std::runtime_error saying which EGL call failed.
class HeadlessContext {
 public:
  HeadlessContext();
  ~HeadlessContext();
  HeadlessContext(const HeadlessContext&) = delete;
  HeadlessContext& operator=(const HeadlessContext&) = delete;
  std::string description() const;  // "llvmpipe (LLVM 15.0.6, 256 bits), 4.5 (Core Profile) ..."

 private:
  void* display_ = nullptr;
  void* context_ = nullptr;
};

// A width x height colour + depth framebuffer, multisampled when samples > 1 (resolved on read).
// Needs a current OpenGL 4.5 context.
class OffscreenTarget {
 public:
  OffscreenTarget(int width, int height, int samples = 4);  // pixels; samples in [1, 8]
  ~OffscreenTarget();
  OffscreenTarget(const OffscreenTarget&) = delete;
  OffscreenTarget& operator=(const OffscreenTarget&) = delete;

  void bind();   // draw into it
  Image read();  // the pixels drawn, rows from the top; waits for the GPU
  int width() const { return width_; }
  int height() const { return height_; }

 private:
  int width_, height_, samples_;
  unsigned draw_fbo_ = 0, colour_ = 0, depth_ = 0;
  unsigned resolve_fbo_ = 0, resolve_colour_ = 0;
};

}  // namespace maille::render
