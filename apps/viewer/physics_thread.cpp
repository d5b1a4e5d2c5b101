#include "physics_thread.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <stdexcept>
#include <utility>

namespace maille::viewer {

namespace {

using Clock = std::chrono::steady_clock;
double seconds(Clock::duration d) {
  return std::chrono::duration<double>(d).count();
}

// A batch of steps runs for at most this long before the physics thread looks at its commands
// and publishes: short enough for the window to get a fresh snapshot every frame at 60 Hz.
constexpr double kBatchSeconds = 1.0 / 120;
// Plot samples per simulated second.
constexpr double kSamplesPerSecond = 100;
// With sound: the physics sleeps while its ring holds more than half its lead, at least this
// long (a shorter sleep is mostly the scheduler's overhead) and at most that (commands).
constexpr double kSoundSleepMin = 0.0005, kSoundSleepMax = 0.01;

}  // namespace

PhysicsThread::PhysicsThread(Model model, SimulationSettings settings,
                             render::SnapshotExchange& out, bool play, SharedContext context)
    : out_(out), context_(std::move(context)) {
  // A device backend is started on the physics thread, where its steps run.
  const std::string backend = std::exchange(settings.backend, "cpu");
  sim_ = make_simulator(std::move(model), std::move(settings));
  running_ = play;
  sim_->publish_now();
  publish_status(0, 0, 0);
  thread_ = std::thread([this] { run(); });
  if (backend != "cpu") set_backend(backend);
}

PhysicsThread::~PhysicsThread() {
  {
    std::lock_guard lock(mutex_);
    quit_ = true;
  }
  wake_.notify_all();
  thread_.join();
}

std::unique_ptr<Simulator> PhysicsThread::make_simulator(Model model, SimulationSettings settings) {
  settings.publish_every = kNeverEvery;  // published explicitly after each batch of steps
  settings.sample_every =
      std::max(1, static_cast<int>(std::lround(1 / (kSamplesPerSecond * settings.step))));
  const bool cpu = settings.backend == "cpu";
  // In the shared context (current on this thread), unless a device was named: that one needs
  // a context of its own, and its snapshots come back through the host.
  if (context_ && settings.backend_options.device < 0)
    settings.backend_options.use_current_context = true;
  auto sim = std::make_unique<Simulator>(std::move(model), std::move(settings));
  if (cpu) sim->add_stage(std::make_unique<DragSpring>(drag_));  // a CPU stage
  sim->set_overlays(true);  // stages' contacts and cells reach the window with the snapshots
  sim->set_device_snapshots(bool(context_));
  // Runs on the physics thread, inside Simulator::publish_now.
  sim->on_publish([this](const Snapshot& s) { out_.publish(s); });
  sim->on_sample([this](const EnergySample& e, const Profile& p) {
    PlotSample sample{e.time, e.energies, {}, {}};
    for (const auto& c : p.counters()) sample.counters.push_back(double(c.last));
    for (const auto& g : p.gauges()) sample.gauges.push_back(g.last);
    std::lock_guard lock(mutex_);
    history_.push_back(std::move(sample));
    while (history_.size() > kHistory) history_.pop_front();
  });
  previous_stage_ns_.clear();
  return sim;
}

void PhysicsThread::send(Command c) {
  {
    std::lock_guard lock(mutex_);
    commands_.push_back(std::move(c));
  }
  wake_.notify_all();
}

void PhysicsThread::play() {
  {
    std::lock_guard lock(mutex_);
    running_ = true;
  }
  wake_.notify_all();
}

void PhysicsThread::pause() {
  std::lock_guard lock(mutex_);
  running_ = false;
}

void PhysicsThread::step_once() {
  {
    std::lock_guard lock(mutex_);
    running_ = false;
    ++single_steps_;
  }
  wake_.notify_all();
}

void PhysicsThread::reset() {
  drag_->release();
  send([this](Simulator& sim) {
    sim.reset();
    source_stale_ = true;  // the listen stage starts again at step 0
    std::lock_guard lock(mutex_);
    history_.clear();
  });
}

void PhysicsThread::set_speed(double speed) {
  std::lock_guard lock(mutex_);
  speed_ = std::max(0.0, speed);
}

void PhysicsThread::set_time_step(double h) {
  send([this, h](Simulator& sim) {
    sim.set_step(h);
    source_stale_ = true;  // the sampling plan follows the step
  });
}

void PhysicsThread::set_integrator(const std::string& name) {
  send([this, name](Simulator& sim) {
    // The simulator converts the velocities (a staggered scheme's half-step velocity is
    // synchronised first) and keeps its model, tuned parameters and stages.
    try {
      source_stale_ = true;  // the switch evaluates forces (the listen stage would hear it)
      sim.set_integrator(name);
      set_notice({});
    } catch (const std::exception& e) {
      set_notice("integrator " + name + ": " + e.what());
    }
  });
}

void PhysicsThread::set_implicit(const ImplicitSettings& implicit) {
  send([this, implicit](Simulator& sim) {
    try {
      source_stale_ = true;
      sim.set_implicit(implicit);
      set_notice({});
    } catch (const std::exception& e) {
      set_notice("implicit solver " + std::string(to_string(implicit.solver)) + ": " + e.what());
    }
  });
}

void PhysicsThread::set_backend(const std::string& name) {
  drag_->release();
  send([this, name](Simulator& sim) {
    if (name == sim.settings().backend) return;
    try {
      SimulationSettings settings = sim.settings();
      settings.backend = name;
      std::unique_ptr<Simulator> next = make_simulator(sim.model(), settings);
      next->restore(sim.state(), sim.frames_published());
      drop_source();  // its listen stage is on the simulator about to go
      source_stale_ = true;
      sim_ = std::move(next);  // `sim` is gone from here on
      set_notice({});
    } catch (const std::exception& e) {
      set_notice("backend " + name + ": " + e.what());
    }
  });
}

void PhysicsThread::scale_link_param(std::size_t pool, std::size_t field, Real factor) {
  send([pool, field, factor](Simulator& sim) {
    sim.edit_parameters([&](Model& m) {
      const auto pools = m.links.pools();
      if (pool < pools.size() && field < pools[pool]->fields().size())
        pools[pool]->scale_param(field, factor);
    });
  });
}

void PhysicsThread::set_fields(const Fields& fields) {
  send([fields](Simulator& sim) { sim.edit_parameters([&](Model& m) { m.fields = fields; }); });
}

void PhysicsThread::set_stage_option(const std::string& stage, const std::string& option,
                                     const std::string& value) {
  send([this, stage, option, value](Simulator& sim) {
    // A refused choice (std::invalid_argument: an unknown name, or a method the scheme cannot
    // run, such as facets under rk4) changes nothing; the panel shows why.
    try {
      sim.set_stage_option(stage, option, value);
      sim.publish_now();  // show the change (drawing options, a new method's colour) when paused
      auto options = sim.stage_options();
      set_notice({});
      std::lock_guard lock(mutex_);
      status_.stage_options = std::move(options);
    } catch (const std::exception& e) {
      set_notice(option + " = " + value + " refused: " + e.what(), stage);
    }
  });
}

void PhysicsThread::start_sound(SoundFeed feed) {
  send([this, feed = std::move(feed)](Simulator&) mutable {
    drop_source();
    control_positions_.clear();  // a new feed: the controls start where the scene has them
    sound_ = std::move(feed);
    source_stale_ = true;
  });
}

void PhysicsThread::stop_sound() {
  send([this](Simulator&) {
    if (sound_) sound_->player->set_producing(false);
    drop_source();
    sound_.reset();
    source_stale_ = false;
    std::lock_guard lock(mutex_);
    status_.sound_notice.clear();
    status_.sound = false;
  });
}

void PhysicsThread::drop_source() {
  if (!source_) return;
  control_positions_ = source_->control_positions();
  source_.reset();  // removes its listen stage from sim_
}

void PhysicsThread::rebuild_source() {
  drop_source();
  source_stale_ = false;
  std::string notice;
  try {
    source_ = std::make_unique<audio::LiveSource>(*sim_, sound_->spec, sound_->player->rate(),
                                                  sound_->tables, sound_->player->block());
    source_->set_control_positions(control_positions_);
  } catch (const std::exception& e) {
    notice = std::string("sound: ") + e.what();
  }
  // Published now, not with the batch's status: a listener may drain a whole change's sound
  // inside the first batch that plays it, and must then read sound on.
  std::lock_guard lock(mutex_);
  status_.sound_notice = std::move(notice);
  status_.sound = source_ != nullptr;
}

// Renders until the ring holds its lead or a batch's time is spent. The producer says it plays
// once the ring has something in it, so the callback's first, empty periods are no xruns.
void PhysicsThread::play_sound() {
  play::RingPlayer& player = *sound_->player;
  player.fill(*source_, sound_->controls.get(), kBatchSeconds);
  player.set_producing(true);
  if (source_->blown_up()) {  // a non-finite sample: the source stopped the model
    player.set_producing(false);
    char text[160];
    std::snprintf(text, sizeof text,
                  "sound: a non-finite sample at %.6f s of sound: the model stopped (reset to "
                  "play again)",
                  source_->blow_up_time());
    std::lock_guard lock(mutex_);
    status_.sound_notice = text;
    running_ = false;
  }
}

void PhysicsThread::set_notice(std::string notice, std::string stage) {
  std::lock_guard lock(mutex_);
  status_.notice = std::move(notice);
  status_.notice_stage = std::move(stage);
}

PhysicsStatus PhysicsThread::status() const {
  std::lock_guard lock(mutex_);
  return status_;
}

std::vector<PlotSample> PhysicsThread::history() const {
  std::lock_guard lock(mutex_);
  return {history_.begin(), history_.end()};
}

bool PhysicsThread::wait_for_step(std::uint64_t steps, double timeout_s) const {
  std::unique_lock lock(mutex_);
  progress_.wait_for(lock, std::chrono::duration<double>(timeout_s),
                     [&] { return status_.step >= steps || status_.blow_up.has_value(); });
  return status_.step >= steps;
}

// Physics thread (and the constructor, before the thread starts).
void PhysicsThread::publish_status(std::uint64_t batch_steps, double batch_wall_s,
                                   double batch_sim_s) {
  const Simulator& sim = *sim_;
  const auto& stages = sim.profile().stages();
  std::vector<StageTime> times;
  previous_stage_ns_.resize(stages.size(), 0);
  for (std::size_t i = 0; i < stages.size(); ++i) {
    const double delta = stages[i].total_ns - previous_stage_ns_[i];
    times.push_back({stages[i].name, batch_steps ? delta / double(batch_steps) : 0.0});
    previous_stage_ns_[i] = stages[i].total_ns;
  }
  std::vector<CounterValue> counters;
  for (const auto& c : sim.profile().counters()) counters.push_back({c.name, c.last});

  auto stage_options = sim.stage_options();
  auto stage_warnings = sim.stage_warnings();
  std::lock_guard lock(mutex_);
  status_.stage_options = std::move(stage_options);
  status_.stage_warnings = std::move(stage_warnings);
  status_.running = running_;
  status_.step = sim.steps_taken();
  status_.time = sim.time();
  status_.step_size = sim.settings().step;
  status_.integrator = sim.settings().integrator;
  status_.implicit = sim.settings().implicit;
  status_.backend = sim.settings().backend;
  if (batch_wall_s > 0) {
    status_.steps_per_second = double(batch_steps) / batch_wall_s;
    status_.realtime_factor = batch_sim_s / batch_wall_s;
  }
  if (sim.blow_up())
    status_.blow_up = sim.blow_up()->message;
  else
    status_.blow_up.reset();
  status_.sound = source_ != nullptr;
  if (batch_steps > 0) status_.stages = std::move(times);
  status_.counters = std::move(counters);
  status_.gauges.clear();
  for (const auto& g : sim.profile().gauges()) status_.gauges.push_back(g.name);
  progress_.notify_all();
}

void PhysicsThread::run() {
  if (context_) context_.make_current();
  // While playing, simulated time follows anchor_sim + (now - anchor_wall) * speed.
  Clock::time_point anchor_wall = Clock::now();
  double anchor_sim = sim_->time();
  bool was_running = false;
  for (;;) {
    std::deque<Command> commands;
    bool running = false;
    int singles = 0;
    double speed = 1;
    bool quit = false;
    {
      std::unique_lock lock(mutex_);
      wake_.wait(lock, [&] { return quit_ || !commands_.empty() || running_ || single_steps_; });
      quit = quit_;
      commands.swap(commands_);
      running = running_;
      singles = std::exchange(single_steps_, 0);
      speed = speed_;
      if (running && sim_->blow_up()) running = running_ = false;  // nothing more to run
    }
    if (quit) {
      // Destroyed on this thread: a device backend's context is current here. The sound's
      // source first: its listen stage is on the simulator.
      source_.reset();
      sim_.reset();
      if (context_) context_.release();
      return;
    }

    for (auto& c : commands) c(*sim_);
    if (sound_ && source_stale_) rebuild_source();
    const bool sounding = sound_ && source_ && !source_->blown_up();
    if (sound_ && !(running && sounding && singles == 0)) sound_->player->set_producing(false);
    const Clock::time_point t0 = Clock::now();
    const double sim0 = sim_->time();
    const std::uint64_t step0 = sim_->steps_taken();

    if (singles > 0) {
      for (int i = 0; i < singles && sim_->step(); ++i) {
      }
      source_stale_ = sound_.has_value();  // steps the source did not take
    } else if (running && sounding) {
      play_sound();  // paced by the sound card, through the ring's fill level
    } else if (running) {
      // A pause, a command or a change of speed restarts the clock: no burst to catch up.
      if (!was_running || !commands.empty()) {
        anchor_wall = t0;
        anchor_sim = sim0;
      }
      const double due = speed > 0 ? anchor_sim + seconds(t0 - anchor_wall) * speed : INFINITY;
      while (sim_->time() < due && seconds(Clock::now() - t0) < kBatchSeconds && sim_->step()) {
      }
      // Too slow for real time: follow from here rather than falling further behind.
      if (speed > 0 && sim_->time() < due - 0.05 * speed) {
        anchor_wall = Clock::now();
        anchor_sim = sim_->time();
      }
    }
    was_running = running && singles == 0;

    const std::uint64_t steps = sim_->steps_taken() - step0;
    if (steps > 0 || !commands.empty()) sim_->publish_now();
    publish_status(steps, seconds(Clock::now() - t0), sim_->time() - sim0);

    // With sound: sleep while the ring is full enough, or until a command arrives.
    if (running && sounding && singles == 0) {
      const double slack =
          std::clamp(sound_->player->seconds_of_slack(), kSoundSleepMin, kSoundSleepMax);
      std::unique_lock lock(mutex_);
      wake_.wait_for(lock, std::chrono::duration<double>(slack),
                     [&] { return quit_ || !commands_.empty() || !running_ || single_steps_; });
    } else if (running && speed > 0 && singles == 0) {
      // Ahead of the clock: sleep until the next step is due or a command arrives.
      const double ahead =
          sim_->time() - (anchor_sim + seconds(Clock::now() - anchor_wall) * speed);
      if (ahead > 0) {
        std::unique_lock lock(mutex_);
        wake_.wait_for(lock, std::chrono::duration<double>(std::min(ahead / speed, 0.01)),
                       [&] { return quit_ || !commands_.empty() || !running_ || single_steps_; });
      }
    }
  }
}

}  // namespace maille::viewer
