#include "maille/render/gl_transfer.hpp"

#include <epoxy/gl.h>

#include <algorithm>

namespace maille::render {

namespace {

GLsync sync(void* s) {
  return static_cast<GLsync>(s);
}

// Waits on the GPU (the calling context's later commands run after the fence), then frees it.
void wait_and_delete(void*& fence) {
  if (!fence) return;
  glWaitSync(sync(fence), 0, GL_TIMEOUT_IGNORED);
  glDeleteSync(sync(fence));
  fence = nullptr;
}

// A fence after everything issued so far, flushed so that another context can wait on it.
void* fence_now() {
  GLsync s = glFenceSync(GL_SYNC_GPU_COMMANDS_COMPLETE, 0);
  glFlush();
  return s;
}

class GlTransfer final : public DeviceTransfer {
 public:
  void write(DeviceSlot& slot, const DevicePositions& from) override {
    wait_and_delete(slot.read);
    if (slot.written) {  // published but never taken: nobody waits on it now
      glDeleteSync(sync(slot.written));
      slot.written = nullptr;
    }
    const std::size_t bytes = std::max<std::size_t>(from.count * 3 * sizeof(float), 16);
    if (slot.capacity < bytes) {
      glDeleteBuffers(1, &slot.buffer);
      glCreateBuffers(1, &slot.buffer);
      glNamedBufferStorage(slot.buffer, GLsizeiptr(bytes), nullptr, 0);
      slot.capacity = bytes;
    }
    // The positions were written by compute shaders: make them visible to the copy.
    glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
    if (from.count > 0)
      glCopyNamedBufferSubData(from.gl_buffer, slot.buffer, 0, 0,
                               GLsizeiptr(from.count * 3 * sizeof(float)));
    slot.written = fence_now();
  }

  void acquire(DeviceSlot& slot) override { wait_and_delete(slot.written); }

  void release(DeviceSlot& slot) override {
    if (slot.read) glDeleteSync(sync(slot.read));
    slot.read = fence_now();
  }

  void destroy(DeviceSlot& slot) override {
    for (void** fence : {&slot.written, &slot.read})
      if (*fence) {
        glDeleteSync(sync(*fence));
        *fence = nullptr;
      }
    glDeleteBuffers(1, &slot.buffer);
    slot.buffer = 0;
    slot.capacity = 0;
  }
};

}  // namespace

std::unique_ptr<DeviceTransfer> make_gl_transfer() {
  return std::make_unique<GlTransfer>();
}

}  // namespace maille::render
