// The hand-off between the physics thread and the render thread: a lock-free triple buffer of
// snapshots. The physics publishes at its own rate and never waits; the renderer takes the latest
// complete snapshot when it draws and never sees one being written. Snapshots (positions,
// overlays, placed solids) are all the two threads share; solids' meshes are
// shared read-only through their shared_ptr, whose count is atomic.
//
//   physics thread                 latest_ (atomic)              render thread
//   writes slots_[back_]  --swap-->  index | fresh  <--swap--   reads slots_[front_]
//
// Each side owns one slot outright; the third is the "latest" slot whose index lives in one
// atomic word with a "fresh" bit. Publishing swaps the written slot in as latest; taking swaps
// the reader's old slot out for the latest. The acquire-release exchanges order the slot's
// contents with its index, so neither side ever touches a slot the other one owns.
//
// Positions left on a GPU (Snapshot::device) travel the same way, with a DeviceTransfer: each
// slot then owns a device buffer, the writer copies the simulator's positions into it on the
// device, and fences order the copy before the reader's draws and those draws before the next
// copy into the same buffer. The two threads' contexts must share objects; the GPU never waits
// on the CPU and nothing is read back.
#pragma once

#include <array>
#include <atomic>
#include <memory>
#include <stdexcept>

#include "maille/snapshot.hpp"

namespace maille::render {

// A slot's share of the device: its copy of the positions and the two fences around it.
struct DeviceSlot {
  std::uint32_t buffer = 0;  // the slot's positions, 3 floats per point
  std::size_t capacity = 0;  // bytes
  void* written = nullptr;   // the copy into `buffer` (set by the writer, waited by the reader)
  void* read = nullptr;      // the reader's last draws from it (set by it, waited by the writer)
};

// How device positions cross between the threads' contexts (gl_transfer.hpp: OpenGL).
class DeviceTransfer {
 public:
  virtual ~DeviceTransfer() = default;
  // Physics thread, its context current: `from` into the slot's buffer, after the reader's
  // draws from it; then the fence the reader waits on.
  virtual void write(DeviceSlot& slot, const DevicePositions& from) = 0;
  virtual void acquire(DeviceSlot& slot) = 0;  // render thread: before drawing from the slot
  virtual void release(DeviceSlot& slot) = 0;  // render thread: after its last draw from it
  virtual void destroy(DeviceSlot& slot) = 0;  // a context of the share group current
};

class SnapshotExchange {
 public:
  // `device`: to hand over snapshots whose positions are on a device; without it, publishing
  // one is a programming error (std::logic_error).
  explicit SnapshotExchange(std::unique_ptr<DeviceTransfer> device = nullptr)
      : device_(std::move(device)) {}
  // Frees the device buffers: a context of the share group must be current, and the writer
  // gone.
  ~SnapshotExchange() {
    if (device_)
      for (DeviceSlot& d : device_slots_) device_->destroy(d);
  }
  SnapshotExchange(const SnapshotExchange&) = delete;
  SnapshotExchange& operator=(const SnapshotExchange&) = delete;

  // Physics thread only. Copies `s` whole (reusing the slot's memory: no allocation once the
  // slots have grown to the model's size, the overlay's and the solids' counts) and makes it the
  // latest. Never blocks.
  void publish(const Snapshot& s) {
    Snapshot& slot = slots_[back_];
    slot.frame = s.frame;
    slot.step = s.step;
    slot.time = s.time;
    slot.positions.assign(s.positions.begin(), s.positions.end());
    slot.device = {};
    if (s.device.gl_buffer != 0) {
      if (!device_) throw std::logic_error("snapshot exchange: device positions need a transfer");
      device_->write(device_slots_[back_], s.device);
      slot.device = {device_slots_[back_].buffer, s.device.count};
    }
    slot.overlay.assign(s.overlay.begin(), s.overlay.end());
    slot.surfaces.assign(s.surfaces.begin(), s.surfaces.end());
    const unsigned previous = latest_.exchange(back_ | kFresh, std::memory_order_acq_rel);
    back_ = previous & kIndex;
  }

  // Render thread only. The latest published snapshot, unchanged until the next call; nullptr
  // before the first publication. `fresh` (optional) is set when it differs from the last call's.
  // With device positions, the context drawing them must be current: the old snapshot's buffer
  // is released after the draws issued so far, the new one's copy is waited for (on the GPU).
  const Snapshot* take(bool* fresh = nullptr) {
    const bool is_new = (latest_.load(std::memory_order_relaxed) & kFresh) != 0;
    if (is_new) {
      if (has_front_ && slots_[front_].device.gl_buffer != 0)
        device_->release(device_slots_[front_]);
      const unsigned previous = latest_.exchange(front_, std::memory_order_acq_rel);
      front_ = previous & kIndex;
      has_front_ = true;
      if (slots_[front_].device.gl_buffer != 0) device_->acquire(device_slots_[front_]);
    }
    if (fresh) *fresh = is_new;
    return has_front_ ? &slots_[front_] : nullptr;
  }

 private:
  static constexpr unsigned kIndex = 3, kFresh = 4;
  std::unique_ptr<DeviceTransfer> device_;
  std::array<Snapshot, 3> slots_;
  std::array<DeviceSlot, 3> device_slots_;  // each owned with its slot
  std::atomic<unsigned> latest_{0};  // slot index of the latest snapshot, | kFresh while unread
  unsigned back_ = 1;                // the physics thread's slot
  unsigned front_ = 2;               // the render thread's slot
  bool has_front_ = false;           // render thread: a snapshot has been taken
};

}  // namespace maille::render
