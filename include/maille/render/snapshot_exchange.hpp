// The hand-off between the physics thread and the render thread: a lock-free triple buffer of
// snapshots. The physics publishes at its own rate and never waits; the renderer takes the latest
// complete snapshot when it draws and never sees one being written. Snapshots (positions,
// overlays, placed solids) are all the two threads share (requirement S5); solids' meshes are
// shared read-only through their shared_ptr, whose count is atomic.
//
//   physics thread                 latest_ (atomic)              render thread
//   writes slots_[back_]  --swap-->  index | fresh  <--swap--   reads slots_[front_]
//
// Each side owns one slot outright; the third is the "latest" slot whose index lives in one
// atomic word with a "fresh" bit. Publishing swaps the written slot in as latest; taking swaps
// the reader's old slot out for the latest. The acquire-release exchanges order the slot's
// contents with its index, so neither side ever touches a slot the other one owns.
#pragma once

#include <array>
#include <atomic>

#include "maille/snapshot.hpp"

namespace maille::render {

class SnapshotExchange {
 public:
  // Physics thread only. Copies `s` whole (reusing the slot's memory: no allocation once the
  // slots have grown to the model's size, the overlay's and the solids' counts) and makes it the
  // latest. Never blocks.
  void publish(const Snapshot& s) {
    Snapshot& slot = slots_[back_];
    slot.frame = s.frame;
    slot.step = s.step;
    slot.time = s.time;
    slot.positions.assign(s.positions.begin(), s.positions.end());
    slot.overlay.assign(s.overlay.begin(), s.overlay.end());
    slot.surfaces.assign(s.surfaces.begin(), s.surfaces.end());
    const unsigned previous = latest_.exchange(back_ | kFresh, std::memory_order_acq_rel);
    back_ = previous & kIndex;
  }

  // Render thread only. The latest published snapshot, unchanged until the next call; nullptr
  // before the first publication. `fresh` (optional) is set when it differs from the last call's.
  const Snapshot* take(bool* fresh = nullptr) {
    const bool is_new = (latest_.load(std::memory_order_relaxed) & kFresh) != 0;
    if (is_new) {
      const unsigned previous = latest_.exchange(front_, std::memory_order_acq_rel);
      front_ = previous & kIndex;
      has_front_ = true;
    }
    if (fresh) *fresh = is_new;
    return has_front_ ? &slots_[front_] : nullptr;
  }

 private:
  static constexpr unsigned kIndex = 3, kFresh = 4;
  std::array<Snapshot, 3> slots_;
  std::atomic<unsigned> latest_{0};  // slot index of the latest snapshot, | kFresh while unread
  unsigned back_ = 1;                // the physics thread's slot
  unsigned front_ = 2;               // the render thread's slot
  bool has_front_ = false;           // render thread: a snapshot has been taken
};

}  // namespace maille::render
