// The viewer's physics: a Simulator running in its own thread at its own rate, publishing
// snapshots into a SnapshotExchange that the window draws from.
//
// The UI thread never touches the simulator. It sends commands (play, pause, step, reset, new
// parameters) that the physics thread applies between two steps, reads a copy of the status and
// the plot histories under a mutex, and moves the drag target through DragState. Pacing: while
// playing, simulated time follows the wall clock times `speed`; when a step costs more than
// that allows, the physics runs as fast as it can and the status shows the real-time factor.
// With sound on (start_sound), the sound card's clock paces it instead: the thread renders the
// scene's [[listen]] channels through a LiveSource into the device's ring (play::RingPlayer)
// whenever the ring falls below its lead, and sleeps while it is full (docs/sound.md, "The
// viewer's Sound panel").
#pragma once

#include <condition_variable>
#include <cstdint>
#include <deque>
#include <functional>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include "drag_spring.hpp"
#include "maille/live.hpp"
#include "maille/render/snapshot_exchange.hpp"
#include "maille/simulator.hpp"
#include "ring_player.hpp"

namespace maille::viewer {

struct StageTime {
  std::string name;
  double ns_per_step = 0;  // averaged over the last batch of steps
};
struct CounterValue {
  std::string name;
  std::uint64_t last = 0;  // during the last step
};

struct PhysicsStatus {
  bool running = false;
  std::uint64_t step = 0;
  double time = 0;       // s, simulated
  double step_size = 0;  // h, s
  std::string integrator;
  ImplicitSettings implicit;  // implicit Euler's solver and its settings
  std::string backend;
  double steps_per_second = 0;  // wall-clock rate over the last batch
  double realtime_factor = 0;   // simulated s per wall s over the last batch
  std::optional<std::string> blow_up;
  std::string notice;        // the last command that could not be applied, and why
  std::string notice_stage;  // the stage it was about (the Stages panel shows it there)
  std::vector<StageTime> stages;
  std::vector<CounterValue> counters;
  std::vector<std::string> gauges;                     // names, in PlotSample::gauges order
  std::vector<Simulator::StageOptions> stage_options;  // plugged-in stages' live settings
  std::vector<std::string> stage_warnings;             // Simulator::stage_warnings
  bool sound = false;        // the listened channels are being rendered (start_sound)
  std::string sound_notice;  // why sound is asked for but not rendered (a GPU backend...)
};

// What the physics thread needs to play the scene's [[listen]] channels into a device's ring.
struct SoundFeed {
  std::shared_ptr<play::RingPlayer> player;      // the device's callback copies from its ring
  std::shared_ptr<play::ControlRings> controls;  // MIDI and OSC events ([[control]]); may be null
  audio::AudioSpec spec;                         // the scene's [[listen]], [audio], [[control]]
  std::vector<audio::ParameterTable> tables;     // per control (empty for an excitation)
};

// One sample of the plots: energies and counters at a simulated time.
struct PlotSample {
  double time = 0;  // s
  Energies energies;
  std::vector<double> counters;  // in PhysicsStatus::counters order
  std::vector<double> gauges;    // in PhysicsStatus::gauges order (a solver's residual...)
};

// An OpenGL context for the physics thread in the window's share group (a hidden window), made
// current when the thread starts and released when it ends. A GPU backend then runs in it and
// publishes its positions on the device: the window draws straight from them through the
// exchange (which needs a DeviceTransfer), and nothing is read back to draw.
struct SharedContext {
  std::function<void()> make_current, release;
  explicit operator bool() const { return bool(make_current); }
};

class PhysicsThread {
 public:
  static constexpr std::size_t kHistory = 400;  // plot samples kept

  // Starts the thread, paused unless `play`. Publishes the initial state at once.
  PhysicsThread(Model model, SimulationSettings settings, render::SnapshotExchange& out, bool play,
                SharedContext context = {});
  ~PhysicsThread();  // stops the thread and joins it
  PhysicsThread(const PhysicsThread&) = delete;
  PhysicsThread& operator=(const PhysicsThread&) = delete;

  void play();
  void pause();
  void step_once();  // pauses and advances one step
  void reset();      // back to the initial state (tuned parameters stay)
  // Simulated seconds per wall-clock second, > 0; or 0: as fast as possible.
  void set_speed(double speed);
  void set_time_step(double h);                         // s, > 0
  void set_integrator(const std::string& name);         // rebuilt around the current state
  void set_implicit(const ImplicitSettings& implicit);  // implicit Euler's solver, likewise
  // Runs the simulation on another backend from the current state (a simulator rebuilt on the
  // physics thread, where a GPU backend's context is current: the shared one when given, else
  // one of its own, whose positions are then downloaded for each snapshot). Refused set-ups keep
  // the old backend and leave a notice. Dragging particles needs the CPU.
  void set_backend(const std::string& name);
  // Multiplies parameter `field` of every link of pool `pool` by `factor` (> 0).
  void scale_link_param(std::size_t pool, std::size_t field, Real factor);
  void set_fields(const Fields& fields);
  // A plugged-in stage's live setting (self-collision on/off, broad phase, drawing...).
  void set_stage_option(const std::string& stage, const std::string& option,
                        const std::string& value);
  // Sound: from the current state on, the physics renders the listened channels into the feed's
  // ring, paced by it (speed is then the sound card's: real time); a LiveSource is rebuilt on
  // the simulator after a reset, a new step, scheme or backend (the GPU backend cannot play:
  // status().sound_notice says so). stop_sound: back to the wall clock.
  void start_sound(SoundFeed feed);
  void stop_sound();

  DragState& drag() { return *drag_; }
  PhysicsStatus status() const;
  std::vector<PlotSample> history() const;
  // Blocks until the simulation has taken at least `steps` steps, stopped on a blow-up, or
  // `timeout_s` passed; returns whether the steps were reached (tests and --frames runs).
  bool wait_for_step(std::uint64_t steps, double timeout_s) const;

 private:
  using Command = std::function<void(Simulator&)>;
  void send(Command c);
  // The last command's refusal (empty: it was applied), and the stage it was about.
  void set_notice(std::string notice, std::string stage = {});
  void run();
  std::unique_ptr<Simulator> make_simulator(Model model, SimulationSettings settings);
  void publish_status(std::uint64_t batch_steps, double batch_wall_s, double batch_sim_s);
  // Sound (physics thread): the LiveSource dropped (before its simulator goes) and made again.
  void drop_source();
  void rebuild_source();
  // One batch paced by the ring; false when nothing could be rendered (the model stopped).
  void play_sound();

  render::SnapshotExchange& out_;
  SharedContext context_;
  std::shared_ptr<DragState> drag_ = std::make_shared<DragState>();
  std::unique_ptr<Simulator> sim_;  // physics thread only, once started

  mutable std::mutex mutex_;                  // guards everything below
  mutable std::condition_variable wake_;      // to the physics thread: commands, quit
  mutable std::condition_variable progress_;  // to waiters: the status changed
  std::deque<Command> commands_;
  bool running_ = false, quit_ = false;
  int single_steps_ = 0;
  double speed_ = 1;
  PhysicsStatus status_;
  std::deque<PlotSample> history_;

  std::vector<double> previous_stage_ns_;  // physics thread only: totals at the last batch
  // Sound, physics thread only: the feed, its source on sim_, whether the source must be made
  // again before the next block, the controls' glide positions carried over to the next one.
  std::optional<SoundFeed> sound_;
  std::unique_ptr<audio::LiveSource> source_;
  bool source_stale_ = false;
  std::vector<double> control_positions_;
  std::thread thread_;  // last: started once everything above exists
};

}  // namespace maille::viewer
