// Rendering with no display: an OpenGL 4.5 core context through EGL on Mesa's "surfaceless"
// platform (no window system, no GPU needed: Mesa's llvmpipe software driver runs it on the CPU),
// and an offscreen framebuffer to draw into and read pixels back from.
#pragma once

#include <string>
#include <vector>

#include "maille/render/image.hpp"

namespace maille::render {

// Creates the context and makes it current on the calling thread. Throws std::runtime_error
// saying which EGL call failed. device < 0: Mesa's surfaceless platform (a GPU when Mesa drives
// one, llvmpipe else); device >= 0: that EGL device (EGL_EXT_device_enumeration: the NVIDIA
// driver's GPUs, Mesa's devices), an error naming how many there are when out of range.
// `share`: a context whose objects (buffers, programs, fences) this one shares, on its display
// (`device` is then ignored). Contexts on one display share its initialisation: the last one
// destroyed terminates it.
class HeadlessContext {
 public:
  explicit HeadlessContext(int device = -1, const HeadlessContext* share = nullptr);
  ~HeadlessContext();
  HeadlessContext(const HeadlessContext&) = delete;
  HeadlessContext& operator=(const HeadlessContext&) = delete;
  std::string description() const;  // "llvmpipe (LLVM 15.0.6, 256 bits), 4.5 (Core Profile) ..."
  // Makes the context current on the calling thread (another thread must have released it).
  void make_current();
  bool is_current() const;
  void release();  // no context current on the calling thread

 private:
  void* display_ = nullptr;
  void* context_ = nullptr;
};

// The EGL devices (EGL_EXT_device_enumeration), each as "index: name (extensions)"; empty when
// the extension is missing.
std::vector<std::string> egl_devices();

// The width x height pixels of a framebuffer, rows from the top (OpenGL's start at the bottom);
// framebuffer 0: the window's back buffer. Needs a current OpenGL context; waits for the GPU.
Image read_framebuffer(unsigned framebuffer, int width, int height);

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
