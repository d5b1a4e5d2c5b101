#include "maille/render/headless.hpp"

#include <epoxy/egl.h>
#include <epoxy/gl.h>

#include <algorithm>
#include <cstdio>
#include <cstring>
#include <map>
#include <mutex>
#include <stdexcept>
#include <string>

namespace maille::render {

namespace {

[[noreturn]] void fail(const char* what) {
  char code[16];
  std::snprintf(code, sizeof code, "0x%04x", eglGetError());
  throw std::runtime_error(std::string("headless OpenGL: ") + what + " failed (EGL error " + code +
                           "); Mesa's EGL (libegl-mesa0) and llvmpipe are needed");
}

// An EGL display is one per process and native display: every context on it shares its
// initialisation, so it is terminated only when the last of them goes (a GPU backend's own
// context must not end the renderer's).
std::mutex displays_mutex;
std::map<EGLDisplay, int> display_users;

void use_display(EGLDisplay display) {
  std::lock_guard lock(displays_mutex);
  if (display_users[display]++ > 0) return;
  EGLint major = 0, minor = 0;
  if (!eglInitialize(display, &major, &minor)) {
    display_users.erase(display);
    fail("eglInitialize");
  }
}

void leave_display(EGLDisplay display) {
  std::lock_guard lock(displays_mutex);
  if (--display_users[display] > 0) return;
  display_users.erase(display);
  eglTerminate(display);
}

}  // namespace

namespace {

bool has_device_enumeration() {
  return epoxy_has_egl_extension(EGL_NO_DISPLAY, "EGL_EXT_device_enumeration") &&
         epoxy_has_egl_extension(EGL_NO_DISPLAY, "EGL_EXT_platform_device");
}

std::vector<EGLDeviceEXT> devices() {
  EGLint count = 0;
  if (!has_device_enumeration() || !eglQueryDevicesEXT(0, nullptr, &count) || count <= 0) return {};
  std::vector<EGLDeviceEXT> out(static_cast<std::size_t>(count));
  if (!eglQueryDevicesEXT(count, out.data(), &count)) return {};
  out.resize(static_cast<std::size_t>(count));
  return out;
}

// Surfaceless: no X server, no GBM device; Mesa picks a GPU when there is one, llvmpipe else.
// The EXT entry point (a client extension): libepoxy cannot tell the EGL version before a
// display exists, so it refuses the EGL 1.5 core eglGetPlatformDisplay here.
EGLDisplay open_display(int device) {
  if (device < 0) {
    if (!epoxy_has_egl_extension(EGL_NO_DISPLAY, "EGL_MESA_platform_surfaceless"))
      throw std::runtime_error(
          "headless OpenGL: EGL lacks EGL_MESA_platform_surfaceless (install libegl-mesa0)");
    EGLDisplay display =
        eglGetPlatformDisplayEXT(EGL_PLATFORM_SURFACELESS_MESA, EGL_DEFAULT_DISPLAY, nullptr);
    if (display == EGL_NO_DISPLAY) fail("eglGetPlatformDisplay(surfaceless)");
    return display;
  }
  const std::vector<EGLDeviceEXT> all = devices();
  if (std::size_t(device) >= all.size())
    throw std::runtime_error(
        "headless OpenGL: no EGL device " + std::to_string(device) + " (this machine has " +
        std::to_string(all.size()) +
        (has_device_enumeration() ? "" : "; EGL_EXT_device_enumeration is missing") + ")");
  EGLDisplay display =
      eglGetPlatformDisplayEXT(EGL_PLATFORM_DEVICE_EXT, all[std::size_t(device)], nullptr);
  if (display == EGL_NO_DISPLAY) fail("eglGetPlatformDisplay(device)");
  return display;
}

}  // namespace

std::vector<std::string> egl_devices() {
  std::vector<std::string> out;
  const std::vector<EGLDeviceEXT> all = devices();
  for (std::size_t i = 0; i < all.size(); ++i) {
    const char* ext = eglQueryDeviceStringEXT(all[i], EGL_EXTENSIONS);
    std::string name = "device";
    const std::string e = ext ? ext : "";
    if (e.find("EGL_MESA_device_software") != std::string::npos)
      name = "software (llvmpipe)";
    else if (e.find("EGL_EXT_device_drm") != std::string::npos)
      name = "DRM device";
    else if (e.find("EGL_NV_device_cuda") != std::string::npos)
      name = "NVIDIA GPU";
    out.push_back(std::to_string(i) + ": " + name + " (" + e + ")");
  }
  return out;
}

HeadlessContext::HeadlessContext(int device, const HeadlessContext* share) {
  EGLDisplay display = share ? share->display_ : open_display(device);
  use_display(display);
  if (!eglBindAPI(EGL_OPENGL_API)) fail("eglBindAPI(OpenGL)");
  const EGLint attributes[] = {EGL_CONTEXT_MAJOR_VERSION,
                               4,
                               EGL_CONTEXT_MINOR_VERSION,
                               5,
                               EGL_CONTEXT_OPENGL_PROFILE_MASK,
                               EGL_CONTEXT_OPENGL_CORE_PROFILE_BIT,
                               EGL_NONE};
  // No config and no surface: everything is drawn into framebuffer objects.
  EGLContext context = eglCreateContext(display, EGL_NO_CONFIG_KHR,
                                        share ? share->context_ : EGL_NO_CONTEXT, attributes);
  if (context == EGL_NO_CONTEXT) {
    leave_display(display);
    fail("eglCreateContext(OpenGL 4.5 core)");
  }
  if (!eglMakeCurrent(display, EGL_NO_SURFACE, EGL_NO_SURFACE, context)) {
    eglDestroyContext(display, context);
    leave_display(display);
    fail("eglMakeCurrent(surfaceless)");
  }
  display_ = display;
  context_ = context;
}

HeadlessContext::~HeadlessContext() {
  if (is_current()) release();  // another context current here stays so
  eglDestroyContext(display_, context_);
  leave_display(display_);
}

void HeadlessContext::make_current() {
  if (is_current()) return;
  if (!eglMakeCurrent(display_, EGL_NO_SURFACE, EGL_NO_SURFACE, context_))
    fail("eglMakeCurrent (is the context current on another thread?)");
}

bool HeadlessContext::is_current() const {
  return eglGetCurrentContext() == context_;
}

void HeadlessContext::release() {
  eglMakeCurrent(display_, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
}

std::string HeadlessContext::description() const {
  const auto* renderer = reinterpret_cast<const char*>(glGetString(GL_RENDERER));
  const auto* version = reinterpret_cast<const char*>(glGetString(GL_VERSION));
  return std::string(renderer ? renderer : "?") + ", OpenGL " + (version ? version : "?");
}

OffscreenTarget::OffscreenTarget(int width, int height, int samples)
    : width_(width), height_(height), samples_(std::clamp(samples, 1, 8)) {
  if (width <= 0 || height <= 0) throw std::invalid_argument("offscreen target: empty size");
  GLint max_samples = 1;
  glGetIntegerv(GL_MAX_SAMPLES, &max_samples);
  samples_ = std::min(samples_, std::max(1, int(max_samples)));
  glCreateFramebuffers(1, &draw_fbo_);
  glCreateRenderbuffers(1, &colour_);
  glCreateRenderbuffers(1, &depth_);
  glNamedRenderbufferStorageMultisample(colour_, samples_ > 1 ? samples_ : 0, GL_RGBA8, width,
                                        height);
  glNamedRenderbufferStorageMultisample(depth_, samples_ > 1 ? samples_ : 0, GL_DEPTH_COMPONENT24,
                                        width, height);
  glNamedFramebufferRenderbuffer(draw_fbo_, GL_COLOR_ATTACHMENT0, GL_RENDERBUFFER, colour_);
  glNamedFramebufferRenderbuffer(draw_fbo_, GL_DEPTH_ATTACHMENT, GL_RENDERBUFFER, depth_);
  if (glCheckNamedFramebufferStatus(draw_fbo_, GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE)
    throw std::runtime_error("offscreen target: framebuffer incomplete");
  if (samples_ > 1) {
    glCreateFramebuffers(1, &resolve_fbo_);
    glCreateRenderbuffers(1, &resolve_colour_);
    glNamedRenderbufferStorage(resolve_colour_, GL_RGBA8, width, height);
    glNamedFramebufferRenderbuffer(resolve_fbo_, GL_COLOR_ATTACHMENT0, GL_RENDERBUFFER,
                                   resolve_colour_);
  }
}

OffscreenTarget::~OffscreenTarget() {
  const GLuint fbos[] = {draw_fbo_, resolve_fbo_};
  const GLuint rbs[] = {colour_, depth_, resolve_colour_};
  glDeleteFramebuffers(2, fbos);
  glDeleteRenderbuffers(3, rbs);
}

void OffscreenTarget::bind() {
  glBindFramebuffer(GL_FRAMEBUFFER, draw_fbo_);
  glViewport(0, 0, width_, height_);
}

Image OffscreenTarget::read() {
  GLuint source = draw_fbo_;
  if (samples_ > 1) {
    glBlitNamedFramebuffer(draw_fbo_, resolve_fbo_, 0, 0, width_, height_, 0, 0, width_, height_,
                           GL_COLOR_BUFFER_BIT, GL_NEAREST);
    source = resolve_fbo_;
  }
  return read_framebuffer(source, width_, height_);
}

Image read_framebuffer(unsigned framebuffer, int width, int height) {
  Image image;
  image.width = width;
  image.height = height;
  const std::size_t row = std::size_t(width) * 3;
  std::vector<std::uint8_t> bottom_up(row * std::size_t(height));
  glBindFramebuffer(GL_READ_FRAMEBUFFER, framebuffer);
  if (framebuffer == 0) glReadBuffer(GL_BACK);
  glPixelStorei(GL_PACK_ALIGNMENT, 1);
  glReadPixels(0, 0, width, height, GL_RGB, GL_UNSIGNED_BYTE, bottom_up.data());
  // OpenGL's rows start at the bottom; images (PNG, video) start at the top.
  image.rgb.resize(bottom_up.size());
  for (int y = 0; y < height; ++y)
    std::memcpy(image.rgb.data() + std::size_t(y) * row,
                bottom_up.data() + std::size_t(height - 1 - y) * row, row);
  return image;
}

}  // namespace maille::render
