// Sound: listeners read one point each every step, and their signals become the channels of a
// WAV file (`[[listen]]`, `[audio]`, `maille run --audio FILE.wav`; docs/sound.md).
//
//   step n:  force pass at t_n --> "listen" stage (last force stage) reads x, v, f of its points
//            (leapfrog's v(n - 1/2) synchronised to t_n with the step's own forces)
//        --> Sampler: exact (keep steps n = k K when h = 1 / (K rate))
//                     or resampled (windowed sinc or linear, from the step times to k / rate)
//        --> channels of float samples at t = k / rate, k = 0, 1, ...
//
// Every sample k is the state at t = k / rate exactly as the scheme has it there (positions at
// t_n, velocities synchronised, the force pass at t_n), never the mix of x(n + 1), v(n + 1/2)
// and f(n) the state holds between steps. A listener reads only its own point: no snapshot.
#pragma once

#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "maille/names.hpp"
#include "maille/vec3.hpp"

namespace maille {

class Simulator;

namespace audio {

enum class Quantity : std::uint8_t {
  position,  // displacement from the point's initial position along the axis, m
  velocity,  // velocity along the axis (synchronised to the sample's time), m/s
  force,     // total force of the force pass on the point along the axis, N (on a fixed point:
             // the reaction, e.g. a string's pull on its bridge)
};

enum class SampleFormat : std::uint8_t { pcm16, float32 };
enum class Resampler : std::uint8_t { sinc, linear };

}  // namespace audio

template <>
struct NameTable<audio::Quantity> {
  static constexpr std::string_view what = "quantity";
  static constexpr std::array<Name<audio::Quantity>, 3> names{{
      {audio::Quantity::position, "position", "displacement from the initial position, m"},
      {audio::Quantity::velocity, "velocity", "velocity synchronised to the sample's time, m/s"},
      {audio::Quantity::force, "force", "total force of the force pass, N"},
  }};
};
template <>
struct NameTable<audio::SampleFormat> {
  static constexpr std::string_view what = "sample format";
  static constexpr std::array<Name<audio::SampleFormat>, 2> names{{
      {audio::SampleFormat::pcm16, "pcm16", "16-bit PCM"},
      {audio::SampleFormat::float32, "float32", "32-bit float"},
  }};
};
template <>
struct NameTable<audio::Resampler> {
  static constexpr std::string_view what = "resampler";
  static constexpr std::array<Name<audio::Resampler>, 2> names{{
      {audio::Resampler::sinc, "sinc", "band-limited windowed sinc"},
      {audio::Resampler::linear, "linear", "linear interpolation"},
  }};
};

namespace audio {

inline std::string_view name(Quantity q) {
  return to_string(q);
}

// One [[listen]] table: one channel.
struct Listener {
  std::string label;        // how the scene named the point: "p8", "string:3", "12"
  std::uint32_t point = 0;  // global point index
  Quantity quantity = Quantity::velocity;
  Vec3 axis{0, 1, 0};  // unit vector (the scene's axis, normalised)
};

constexpr int min_rate = 1000;    // Hz
constexpr int max_rate = 384000;  // Hz

// [audio]
struct AudioSettings {
  int rate = 44100;  // samples per second, [min_rate, max_rate]
  SampleFormat format = SampleFormat::pcm16;
  // 0: automatic, the largest |value| at 0.99 of full scale, one gain per quantity (see
  // output_gains); > 0: sample = gain x value on every channel (PCM clips at +-1).
  double gain = 0;
  // Used when the step is not 1 / (K rate) for a whole K (docs/sound.md, "Resampling").
  Resampler resampler = Resampler::sinc;
  // `maille play` (docs/sound.md, "Playing live"): the UDP port of the OSC server (0: none), the
  // address it listens on, and the name of the virtual MIDI input port the program creates.
  int osc_port = 0;
  std::string osc_host = "127.0.0.1";
  std::string midi_port = "maille";
};

// What a [[control]] listens to on MIDI.
enum class MidiSource : std::uint8_t { none, cc, note, pitchbend };

// An excitation a control gives (`excite = { point, quantity, axis, amount }`): every point
// named gains amount x s along the axis, s in [0, 1] the gesture's strength (a note's velocity
// / 127, an OSC float). velocity: m/s (a strike: an impulse of m x that); position: m (a pluck).
struct Excitation {
  std::string label;                       // the point or group as the scene named it
  std::vector<std::uint32_t> points;       // global indices
  Quantity quantity = Quantity::velocity;  // velocity or position
  Vec3 axis{0, 1, 0};                      // unit vector
  double amount = 1;
};

// One [[control]] table: a MIDI and/or OSC source mapped onto a scene key (a live parameter
// edit, smoothed) or an excitation.
struct Control {
  MidiSource midi = MidiSource::none;
  int midi_number = 0;       // the controller of "cc:N", 0..127
  int midi_channel = 0;      // 1..16; 0: any
  std::string osc;           // an OSC address ("/maille/wind"); empty: none
  std::string key;           // a --set key (empty for an excitation)
  double low = 0, high = 1;  // range: MIDI 0..127 and OSC [0, 1] map onto [low, high]
  double smooth = 0.02;      // s: a parameter glides to a new value over this time
  std::optional<Excitation> excite;
  // Where the table's key is (its `key`, else its first line), for errors found when playing
  // starts (a key that cannot change live).
  std::string file;
  int line = 0, column = 0;
  std::string name;  // "control[i]"
};

struct AudioSpec {
  std::vector<Listener> listeners;  // [[listen]] tables in file order: channel 0, 1, ...
  AudioSettings settings;           // [audio] (defaults when the table is absent)
  std::vector<Control> controls;    // [[control]] tables in file order (`maille play`)
};

// How steps of h seconds become samples at `rate`.
struct SamplingPlan {
  bool exact = false;                  // h = 1 / (K rate) to 1e-9 relative: every K-th step is kept
  std::uint64_t steps_per_sample = 0;  // K when exact
  double step = 0;                     // h, s
  int rate = 0;                        // Hz
  Resampler resampler = Resampler::sinc;  // when not exact
  std::string describe() const;  // "exact: every 2 steps" / "resampled (windowed sinc) ..."
};
SamplingPlan plan_sampling(double step, int rate, Resampler resampler);

// Streaming resamplers from samples at n h (n = 0, 1, ...) to samples at k / rate.
//  sinc:   band-limited interpolation, y(t) = sum x_n g(t - n h) / sum g(t - n h), with g a
//          Blackman-windowed sinc of cutoff fc = 0.45 min(rate, 1/h) and 16 zero crossings each
//          side (stopband below -70 dB): content above 0.45 rate is removed, not aliased
//  linear: the straight line between the two steps around t; the error on a sinusoid of
//          frequency f is at most (pi f h)^2 / 2 of its amplitude, and content above rate / 2
//          aliases
// A sample is produced once the inputs its kernel spans have arrived; finish() produces the
// rest up to the last input's time (the sinc kernel truncated there, its weights renormalised).
class StreamResampler {
 public:
  StreamResampler(double in_step, int out_rate, Resampler kind);
  void push(double x);
  void finish();
  void reserve_input(std::size_t n) { in_.reserve(n); }  // no allocation while playing
  std::vector<float>& out() { return out_; }

 private:
  void emit(bool final);
  double sample_at(double t) const;

  double h_, rate_;
  Resampler kind_;
  double cutoff_ = 0, half_width_ = 0;  // fc, Hz; kernel half-width, s
  std::vector<double> in_;              // inputs from index first_ on
  std::uint64_t first_ = 0, pushed_ = 0, emitted_ = 0;
  std::vector<float> out_;
};

// The force stage that reads the listened points (the Recorder's, live play's): one name for the
// profile's ns_listen column.
inline constexpr std::string_view kListenStage = "listen";

// The signals of a set of listeners, as a simulator runs. attach() installs a force stage named
// kListenStage (the last force stage, so that it reads the complete force) in the simulator; it
// records the first force pass of every step (multi-pass schemes evaluate again at intermediate
// states: those are skipped) and the pass an end-of-run energy check makes at the final time.
class Recorder {
 public:
  // `force_resample`: resample even when the step divides 1 / rate (tests compare both paths).
  Recorder(AudioSpec spec, double step, bool force_resample = false);
  ~Recorder();
  Recorder(const Recorder&) = delete;
  Recorder& operator=(const Recorder&) = delete;

  // Throws std::invalid_argument when the simulator refuses the stage (the GPU backend keeps
  // the state on the device: listening needs the CPU's), or its step or time is not the one the
  // recorder was made for (a resumed run).
  void attach(Simulator& sim);
  // Flushes the resamplers; channels are cut where a value was not finite (a blow-up) so that
  // every channel has the same length. Idempotent.
  void finish();
  // One vector per listener, samples at k / rate from k = 0; complete after finish().
  const std::vector<std::vector<float>>& channels() const;
  const AudioSpec& spec() const;
  const SamplingPlan& plan() const;
  // Force passes read (one per step, plus the final time).
  std::uint64_t steps_heard() const;

  struct Tap;  // shared with the stage, which may outlive the recorder inside the simulator

 private:
  std::shared_ptr<Tap> tap_;
};

// The gain of each channel for writing: settings.gain for every channel when it is set; else
// automatic, one gain per quantity (channels of the same quantity share it, so their relative
// levels are kept; a force in N and a velocity in m/s are not comparable anyway): 0.99 / the
// largest |sample| among them (1 for silence).
std::vector<double> output_gains(const std::vector<std::vector<float>>& channels,
                                 const AudioSpec& spec);

}  // namespace audio
}  // namespace maille
