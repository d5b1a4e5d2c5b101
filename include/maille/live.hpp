// Playing a model live (`maille play`, docs/sound.md "Playing live"): the model rendered block by
// block at the device's rate, its [[control]] tables applied between samples.
//
//   MIDI / OSC threads --ControlEvent (lock-free rings, owned by the app)--> audio callback
//   audio callback:   LiveSource::control() for each event, then LiveSource::render(block):
//                     per sample: glide the controls' values, K steps of the simulator, the
//                     "live_listen" stage reads the channels at the sample's step
//
// Nothing in control() or render() allocates, locks or does I/O: parameter edits write values
// that were all validated before playing started (ParameterTable: each row is a model read from
// the scene through --set's path, checked like any scene), and excitations write velocities or
// positions of the state.
#pragma once

#include <array>
#include <atomic>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "maille/audio.hpp"
#include "maille/model.hpp"

namespace maille {

class Simulator;
class Stage;

namespace audio {

// A gesture for control `control`, already clamped to [0, 1] by the sender. value: where the
// key goes in its range (a CC / 127, a note's number / 127, the pitch bend from 0 (down) to 1
// (up), an OSC float); strength: how hard an excitation acts (a note's velocity / 127; the
// value itself for the other sources).
struct ControlEvent {
  std::uint32_t control = 0;
  float value = 0;
  float strength = 0;
};

// How one MIDI message maps onto spec's controls: one event per control it reaches (its source
// and channel), at most out_size, into out; returns how many. Note-on with velocity > 0 (the
// number places a key, the velocity / 127 is the strength), control change (value / 127), pitch
// bend (14 bits / 16383, 8192 the middle); everything else is ignored. No allocation.
std::size_t midi_events(const AudioSpec& spec, const unsigned char* msg, std::size_t size,
                        ControlEvent* out, std::size_t out_size);

// One producer, one consumer, fixed capacity (a power of two), lock-free.
template <class T, std::size_t N>
class SpscRing {
  static_assert((N & (N - 1)) == 0, "N must be a power of two");

 public:
  bool push(const T& item) {  // producer; false when full (the item is dropped)
    const std::size_t w = write_.load(std::memory_order_relaxed);
    if (w - read_.load(std::memory_order_acquire) == N) return false;
    items_[w & (N - 1)] = item;
    write_.store(w + 1, std::memory_order_release);
    return true;
  }
  bool pop(T& item) {  // consumer; false when empty
    const std::size_t r = read_.load(std::memory_order_relaxed);
    if (r == write_.load(std::memory_order_acquire)) return false;
    item = items_[r & (N - 1)];
    read_.store(r + 1, std::memory_order_release);
    return true;
  }
  static_assert(std::atomic<std::size_t>::is_always_lock_free);

 private:
  std::array<T, N> items_{};
  alignas(64) std::atomic<std::size_t> write_{0};
  alignas(64) std::atomic<std::size_t> read_{0};
};

// A value of the model that may change while it plays: a link's parameter, a field's component,
// a point's mass, a drive's path parameter. A flat numbering over the model (parameter_slots).
struct ParameterSlot {
  enum class Kind : std::uint8_t { link, field, mass, drive } kind = Kind::link;
  std::uint32_t pool = 0;   // link: the pool's index in LinkSet::pools()
  std::uint32_t index = 0;  // link: the link's id; mass: the point; drive: the drive
  std::uint32_t field = 0;  // link: the field; field / drive: the component (see the .cpp)
};
// Every slot of `m` and its values, in the same order.
std::vector<ParameterSlot> parameter_slots(const Model& m);
std::vector<double> parameter_values(const Model& m);
// Writes one slot (a free point's mass writes its inverse too). No allocation.
void set_parameter(Model& m, const ParameterSlot& slot, double value);
// "spring_damper link 12 stiffness", "fields.air_drag", "mass of point 3", ...
std::string describe(const Model& m, const ParameterSlot& slot);

// What a parameter control writes: the model's slots its key changes, tabulated at `rows`
// values of the key spread evenly over [low, high]; a value in between is the piecewise-linear
// blend of the two rows around it (exact when the model depends linearly on the key, which is
// checked: build_parameter_table in the scene library uses 2 rows then, else 33).
struct ParameterTable {
  std::vector<ParameterSlot> slots;
  std::vector<double> values;  // rows x slots.size()
  std::size_t rows = 0;
  double initial = 0;  // the scene's own value of the key, as a position in [0, 1] of the range
  double max_blend_error = 0;  // relative, measured at the midpoints of the rows (0: linear)
};

// The model rendered at the device's rate. `tables[c]` belongs to spec.controls[c] (empty for
// an excitation). The step divides 1 / rate (exact) or not (resampled then, docs/sound.md
// "Sampling"). Sample 0 is the simulator's state when the source is made (t = 0 for `maille
// play`; wherever the viewer's model is when its sound starts); from there the simulator is
// stepped only by render(), and its step stays as it was: a step changed, a reset or a new
// simulator needs a new LiveSource. The source installs a listen stage on `sim` and removes it
// when destroyed, so it must be destroyed before `sim`.
class LiveSource {
 public:
  LiveSource(Simulator& sim, const AudioSpec& spec, int rate, std::vector<ParameterTable> tables,
             std::size_t max_frames);
  ~LiveSource();  // uninstalls the listen stage (the simulator must still exist)
  LiveSource(const LiveSource&) = delete;
  LiveSource& operator=(const LiveSource&) = delete;

  // Between blocks, in the audio thread. Parameter controls glide to `value` over their
  // `smooth` time; excitations act at once (before the next sample).
  void control(const ControlEvent& e);
  // `frames` samples of every channel, interleaved, into out (frames <= max_frames). After a
  // blow-up (a non-finite sample) the model stops and the rest is silence.
  void render(float* out, std::size_t frames);

  std::size_t channels() const;
  const SamplingPlan& plan() const;
  std::uint64_t frames() const;   // rendered so far
  bool blown_up() const;          // a non-finite value was heard: the model stopped
  double blow_up_time() const;    // s, the sample's time
  std::uint64_t clipped() const;  // samples sent beyond [-1, 1]
  // The gains in use: [audio] gain, or (auto) 0.99 / the largest |value| heard so far per
  // quantity, never rising (a causal version of run --audio's automatic gain).
  std::vector<double> gains() const;
  // The current value of control c in its range's units (a parameter's glide position).
  double control_value(std::size_t c) const;
  // Every parameter control's glide position in [0, 1], and the same set again without writing
  // the model (a new source on a simulator whose parameters those positions already tuned: the
  // viewer rebuilds its source after a reset, a new step or a new backend).
  std::vector<double> control_positions() const;
  void set_control_positions(const std::vector<double>& positions);

  struct Impl;

 private:
  std::unique_ptr<Impl> impl_;
  const Stage* stage_ = nullptr;  // the listen stage installed on the simulator
};

}  // namespace audio
}  // namespace maille
