// maille.Simulation: a Simulator driven from Python (the class; simulation.cpp binds it).
//
// Bit-identity with `maille run`: a scene is loaded with the same call (load_scene with the
// overrides as `--set` strings), the simulator is built with the same settings, and step() and
// run() call Simulator::step() and nothing else between steps; the module links the very objects
// the command line links. Nothing here changes a state between two steps unless asked
// (energies() restores the force array and the stages' memory it evaluates through).
//
// Views: positions and velocities are NumPy arrays over State::x() and State::v() (n contiguous
// Vec3 of 3 Reals), whose base is the Python Simulation (the array keeps it alive). The buffers
// never move while the simulation lives: reset() and load_checkpoint() copy into them, and a live
// edit that would change the point count is refused. With a device backend, the host copy is
// brought up to date whenever control returns to Python, and marked as changed (so the device
// is reloaded before the next step, with whatever Python wrote).
//
// The GIL is released while stepping and taken back for callbacks and, every 0.1 s, to let
// Python handle signals (Ctrl-C raises KeyboardInterrupt between two steps).
#pragma once

#include <atomic>
#include <cmath>
#include <memory>
#include <optional>
#include <thread>
#include <type_traits>

#include "bindings.hpp"
#include "maille/checkpoint.hpp"
#include "maille/io.hpp"
#include "maille/limits.hpp"
#include "maille/live_settings.hpp"
#include "signal_poll.hpp"

namespace maille::python {

class Simulation {
 public:
  // From a scene file (with overrides), or from a model built in code.
  Simulation(const py::object& source, const py::object& overrides, const py::object& threads,
             const py::object& step, const py::object& integrator) {
    const std::string where = "<maille.Simulation>";
    std::vector<std::string> sets = overrides_from(overrides);
    // Keyword settings as overrides, validated like the scene's own keys.
    if (!step.is_none())
      merge_override(sets,
                     override_text("simulation.step", py::float_(real_arg(step, where, "step"))));
    if (!integrator.is_none())
      merge_override(sets, override_text("simulation.integrator",
                                         py::str(str_of(integrator, where, "integrator"))));
    if (!threads.is_none()) {
      const long long n = int_arg(threads, where, "threads");
      if (n < 1 || n > limits::max_threads)
        fail(where, "threads", "must be in [1, 1024] (got " + std::to_string(n) + ")");
      merge_override(sets, "simulation.threads=" + std::to_string(n));
    }
    Scene scene;
    if (py::isinstance<CodeModel>(source)) {
      const CodeModel& cm = source.cast<const CodeModel&>();
      if (cm.model.points.size() == 0)
        fail("<maille.Simulation>", "model", "the model has no point (add_point or a builder)");
      code_settings_ = cm.settings;
      std::vector<std::string> all = cm.settings;
      all.insert(all.end(), sets.begin(), sets.end());
      scene = settings_scene(all);
      scene.name = "model";
      const Fields fields = scene.model.fields;  // the code model with the fields read
      scene.model = cm.model;
      scene.model.fields = fields;
      from_code_ = true;
    } else {
      source_ = path_arg(source, where, "source");
      try {
        scene = value_or_throw(load_scene(source_, sets));
      } catch (const std::bad_alloc&) {
        fail(source_.string(), "", "out of memory while building the scene");
      }
    }
    sets_ = std::move(sets);
    name_ = scene.name;
    loaded_ = scene.settings;
    try {
      sim_ = std::make_unique<Simulator>(std::move(scene.model), scene.settings);
    } catch (const std::invalid_argument& e) {
      fail(from_code_ ? "<maille.Model>" : source_.string(), "", e.what());
    }
    sim_->on_sample([this](const EnergySample& e, const Profile& p) { record(e, p); });
    sim_->on_stop_request([this] { return signals_.pending(); });
    // What `maille validate` and `maille run` print as warnings (a key the solver does not
    // read, a stage's advice), as Python warnings.
    for (const std::string& w : sim_->stage_warnings())
      if (PyErr_WarnEx(PyExc_UserWarning, ("maille: " + w).c_str(), 1) != 0)
        throw py::error_already_set();
    sim_->on_publish([this](const Snapshot& s) {
      if (capture_) captured_ = s;
    });
  }

  // --- stepping ------------------------------------------------------------------------------

  std::uint64_t step(const py::object& count) {
    const long long n = int_arg(count, "<maille.Simulation.step>", "n");
    if (n < 0) fail("<maille.Simulation.step>", "n", "must be >= 0");
    Busy busy(*this);
    return advance(static_cast<std::uint64_t>(n));
  }

  // `steps` steps, or `duration` seconds from now, or (neither) until the scene's duration
  // counted from t = 0, as `maille run` does; callback(sim) after every `every` steps (the
  // scene's output_every by default), stopping when it returns False. Returns the steps taken.
  std::uint64_t run(const py::object& duration, const py::object& steps, const py::object& every,
                    const py::object& callback, const py::object& self) {
    const std::string where = "<maille.Simulation.run>";
    Busy reading(*this);  // the settings and the step count, then released for the run
    const double h = sim_->settings().step;
    std::uint64_t total = 0;
    if (!steps.is_none()) {
      const long long s = int_arg(steps, where, "steps");
      if (s < 0 || double(s) > double(limits::max_steps))
        fail(where, "steps", "must be in [0, 1e12]");
      total = static_cast<std::uint64_t>(s);
    } else {
      const bool given = !duration.is_none();
      const double d = given ? real_arg(duration, where, "duration") : duration_of_scene();
      if (!std::isfinite(d) || d < 0) fail(where, "duration", "must be a finite number >= 0");
      const double n = std::round(d / h);
      if (!(n <= double(limits::max_steps)))
        fail(where, "duration", "is more than 1e12 steps at this step size");
      const auto wanted = static_cast<std::uint64_t>(n);
      total = given ? wanted : (wanted > sim_->steps_taken() ? wanted - sim_->steps_taken() : 0);
    }
    long long k = every.is_none() ? sim_->settings().publish_every : int_arg(every, where, "every");
    if (k < 1) fail(where, "every", "must be >= 1");
    reading.release();
    if (!callback.is_none() && !PyCallable_Check(callback.ptr()))
      throw py::type_error(where + ": argument 'callback' must be callable (got " +
                           py::str(callback.get_type().attr("__name__")).cast<std::string>() + ")");
    Busy busy(*this);
    if (callback.is_none()) return advance(total);
    std::uint64_t done = 0;
    while (done < total) {
      done += advance(std::min<std::uint64_t>(static_cast<std::uint64_t>(k), total - done));
      busy.release();  // the callback may step, edit, save...
      const py::object r = callback(self);
      busy.acquire();
      if (r.is_none()) continue;
      const int truth = PyObject_IsTrue(r.ptr());  // False, 0, np.False_ ... stop the run
      if (truth < 0) throw py::error_already_set();
      if (truth == 0) break;
    }
    return done;
  }

  // --- views and queries ---------------------------------------------------------------------

  py::array_t<Real> view(int which, const py::object& self) {
    Busy busy(*this);
    State& s = state();
    Vec3* data = which == 0 ? s.x().data() : s.v().data();
    return py::array_t<Real>({static_cast<py::ssize_t>(s.size()), py::ssize_t{3}},
                             {py::ssize_t(sizeof(Vec3)), py::ssize_t(sizeof(Real))},
                             reinterpret_cast<Real*>(data), self);
  }

  py::dict energies() {
    Busy busy(*this);
    const Energies e = keeping_forces([this] { return sim_->energies(); });
    py::dict d;
    for_each_energy(e, [&](const char* name, double value) { d[name] = value; });
    return d;
  }

  py::dict stats() {
    Busy busy(*this);  // a sample being recorded by a stepping thread is not read half-written
    // Step and counters are integers in stats.csv: ints here too.
    py::dict d;
    for (const StatColumn& c : stats_)
      d[py::str(c.name)] =
          c.integer ? py::object(py::int_(c.count)) : py::object(py::float_(c.value));
    return d;
  }

  // --- live edits ----------------------------------------------------------------------------

  void set(const py::object& key_object, const py::object& value) {
    const std::string key = key_arg(key_object, "<maille.Simulation.set>", "key");
    Busy busy(*this);
    std::vector<std::string> sets = sets_;
    merge_override(sets, override_text(key, value));
    if (from_code_ && key.rfind("fields.", 0) != 0 && key.rfind("simulation.", 0) != 0)
      fail("<maille.Simulation.set>", key,
           "a simulation of a model built in code takes fields.* and simulation.* keys");
    Scene scene;
    if (from_code_) {
      std::vector<std::string> all = code_settings_;
      all.insert(all.end(), sets.begin(), sets.end());
      scene = settings_scene(all);
    } else {
      scene = value_or_throw(load_scene(source_, sets));
    }
    const std::string_view changed = fixed_setting_changed(loaded_, scene.settings);
    if (!changed.empty())
      fail("--set", key,
           "simulation." + std::string(changed) +
               " cannot change while the simulation runs: give it in overrides= when making "
               "the Simulation (live: " +
               live_setting_keys() + ", fields, links' and builders' parameters)");
    const std::uint32_t n = sim_->model().points.size();
    if (!from_code_ && scene.model.points.size() != n)
      fail("--set", key,
           "changes the number of points (" + std::to_string(n) + " -> " +
               std::to_string(scene.model.points.size()) +
               "), which a live edit cannot do (the views would lose their memory): give it in "
               "overrides= when making the Simulation");
    try {
      // The model first (the scheme is checked against it), then the step and the scheme.
      if (from_code_) {
        const Fields fields = scene.model.fields;
        sim_->edit_parameters([&](Model& m) { m.fields = fields; });
      } else if (key.rfind("simulation.", 0) != 0) {
        // Every other key may change the model (a field, a builder's or a link's parameter, a
        // drive, a stage's table): the model read replaces the running one, state kept.
        sim_->edit_model([&](Model& m) { m = std::move(scene.model); });
      }
      apply_live_settings(*sim_, scene.settings);  // step, scheme, implicit solver
    } catch (const std::invalid_argument& e) {
      fail("--set", key, e.what());
    }
    loaded_ = scene.settings;
    sets_ = std::move(sets);
    sync_for_python();
  }

  // --- checkpoints ---------------------------------------------------------------------------

  void save_checkpoint(const py::object& path_object) {
    const std::string path = path_arg(path_object, "<maille.Simulation.save_checkpoint>", "path");
    Busy busy(*this);
    const Checkpoint c{sim_->state(),         sim_->settings().integrator,
                       sim_->settings().step, sim_->frames_published(),
                       stats_rows_,           model_fingerprint(sim_->model(), sim_->settings())};
    try {
      write_checkpoint(path, c);
    } catch (const std::runtime_error& e) {
      PyErr_SetString(PyExc_OSError, e.what());
      throw py::error_already_set();
    }
  }

  void load_checkpoint(const py::object& path_object) {
    const std::string path = path_arg(path_object, "<maille.Simulation.load_checkpoint>", "path");
    Busy busy(*this);
    Result<Checkpoint> r =
        read_checkpoint(path, model_fingerprint(sim_->model(), sim_->settings()));
    if (!r) throw CheckpointError(r.error());
    Checkpoint& c = r.value();
    if (c.integrator != sim_->settings().integrator || c.step != sim_->settings().step)
      throw CheckpointError(
          InputError{path, 0, 0, "simulation.step",
                     scheme_mismatch(c.integrator, c.step, "the simulation runs",
                                     sim_->settings().integrator, sim_->settings().step)});
    replace_state(c.state, c.frames_published);
    stats_rows_ = c.stats_rows;
  }

  void reset() {
    Busy busy(*this);
    State kept = std::move(sim_->state_for_editing());  // the buffers the views see
    sim_->reset();
    const State fresh = sim_->state();
    sim_->restore(std::move(kept));
    replace_state(fresh, 0);
    stats_.clear();
    stats_rows_ = 0;
  }

  // --- rendering -----------------------------------------------------------------------------

  void render(const py::object& path_object, const py::object& width_object,
              const py::object& height_object, const py::object& camera,
              const py::object& samples_object, const py::object& mesh_object) {
    const std::string where = "<maille.Simulation.render>";
    const std::string path = path_arg(path_object, where, "path");
    const long long width = int_arg(width_object, where, "width");
    const long long height = int_arg(height_object, where, "height");
    const long long samples = int_arg(samples_object, where, "samples");
    const bool mesh = bool_arg(mesh_object, where, "mesh");
    if (!render_available())
      throw std::runtime_error(
          "render: this maille module was built without rendering (MAILLE_BUILD_RENDER=OFF, or "
          "without OpenGL/EGL); save positions and render elsewhere");
    if (width < 1 || width > 16384) fail(where, "width", "must be in [1, 16384]");
    if (height < 1 || height > 16384) fail(where, "height", "must be in [1, 16384]");
    if (samples < 1 || samples > 8) fail(where, "samples", "must be in [1, 8]");
    if (std::filesystem::path(path).extension() != ".png")
      fail(where, "path", "must name a .png file (videos: `maille render`)");
    StillOptions o;
    o.width = int(width);
    o.height = int(height);
    o.samples = int(samples);
    o.mesh = mesh;
    if (!camera.is_none()) {
      std::vector<double> c;
      if (py::isinstance<py::str>(camera) || !py::isinstance<py::sequence>(camera))
        throw py::type_error(where + ": argument 'camera' must be a sequence (yaw, pitch[, zoom])");
      for (const auto& item : camera.cast<py::sequence>())
        c.push_back(real_arg(item, where, "camera"));
      if (c.size() < 2 || c.size() > 3)
        fail(where, "camera", "must be (yaw, pitch[, zoom]) in degrees");
      if (!std::isfinite(c[0]) || !(std::abs(c[1]) <= 89) ||
          (c.size() == 3 && !(c[2] > 0.001 && c[2] <= 1000)))
        fail(where, "camera", "yaw finite, pitch within +-89 degrees, zoom in (0.001, 1000]");
      o.yaw = c[0];
      o.pitch = c[1];
      if (c.size() == 3) o.zoom = c[2];
    }
    Busy busy(*this);
    capture_ = true;
    sim_->publish_now();
    capture_ = false;
    Snapshot snapshot = std::move(captured_);
    captured_ = Snapshot{};
    {
      py::gil_scoped_release release;
      render_still(sim_->model(), snapshot, path, o);
    }
  }

  // --- accessors -----------------------------------------------------------------------------

  Simulator& sim() { return *sim_; }
  const std::string& name() const { return name_; }
  double duration_of_scene() const { return loaded_.duration; }
  std::string velocity_time() {
    return sim_->integrator().velocity_time(state()) == VelocityTime::half_step ? "half_step"
                                                                                : "synchronous";
  }
  std::uint64_t hash() {
    Busy busy(*this);
    return state_hash(state());
  }
  // The overrides that made this simulation what it is: construction's, then live edits, one
  // per key (the latest value).
  std::vector<std::string> overrides() {
    Busy busy(*this);
    return sets_;
  }
  // `f(simulator)` under the same guard as the methods: another thread stepping is refused
  // rather than read half-way.
  template <class F>
  auto read(F&& f) {
    Busy busy(*this);
    return f(static_cast<const Simulator&>(*sim_));
  }

 private:
  // One thread at a time: a second thread calling in while this one steps (GIL released) is
  // refused rather than racing.
  class Busy {
   public:
    explicit Busy(Simulation& s) : s_(s) { acquire(); }
    ~Busy() {
      if (held_) s_.busy_ = false;
    }
    void acquire() {
      // A device backend's OpenGL context is current on the thread that made it, and a context
      // is current on one thread at a time: calls from another thread are refused by name.
      if (s_.sim_ && s_.sim_->backend() && std::this_thread::get_id() != s_.owner_)
        throw std::runtime_error(
            "this simulation runs on the GPU backend, whose OpenGL context belongs to the thread "
            "that created the Simulation: call it from that thread (docs/python.md)");
      if (s_.busy_.exchange(true))
        throw std::runtime_error("the simulation is busy in another thread (or a callback)");
      held_ = true;
    }
    void release() {
      s_.busy_ = false;
      held_ = false;
    }

   private:
    Simulation& s_;
    bool held_ = false;
  };

  // The host state, current, and marked as changed for a device backend (Python may write it).
  State& state() { return sim_->state_for_editing(); }
  void sync_for_python() {
    if (sim_->backend()) sim_->state_for_editing();
  }

  // Steps with the GIL released. The GIL is taken back every 0.1 s (between steps, and inside
  // long steps through the stop poll, SignalPoll::pending) to let Python run its signal handlers:
  // Ctrl-C raises KeyboardInterrupt between two steps, or abandons a step in progress (the
  // simulator puts back the state of the last whole step). The GIL is released and taken back
  // by hand rather than by gil_scoped_release, whose destructor is noexcept: a daemon thread
  // stepping while the interpreter exits is ended by Python inside PyEval_RestoreThread
  // (pthread_exit, an unwinding), which a noexcept frame turns into std::terminate.
  std::uint64_t advance(std::uint64_t n) {
    std::uint64_t done = 0;
    bool fine = true;
    check_written_state();
    signals_.start();
    PyThreadState* released = PyEval_SaveThread();
    try {
      while (done < n) {
        if (_Py_IsFinalizing()) SignalPoll::park();  // the interpreter is going: step no more
        if (!sim_->step()) {
          fine = false;
          break;
        }
        ++done;
        if ((done & 15) == 0 && signals_.pending()) {
          fine = false;
          break;
        }
      }
    } catch (const std::invalid_argument& e) {
      // A stage refusing its work (more contact pairs than the memory budget): the scene's.
      PyEval_RestoreThread(released);
      fail(from_code_ ? "<maille.Model>" : source_.string(), "", e.what());
    } catch (...) {
      PyEval_RestoreThread(released);
      throw;
    }
    PyEval_RestoreThread(released);
    sync_for_python();
    signals_.raise_if_pending();
    if (!fine) {
      if (sim_->blow_up()) throw BlowUpError(*sim_->blow_up());
      throw std::runtime_error("the simulation stopped");
    }
    check_before_returning();
    return done;
  }

  // Values Python wrote into the views are checked before any step sees them: a NaN or an
  // infinite position reaching a stage's grid is a BlowUp naming the point, not a crash.
  void check_written_state() {
    const State& s = sim_->state();
    const auto x = s.x(), v = s.v();
    for (std::size_t i = 0; i < x.size(); ++i)
      if (!is_finite(x[i]) || !is_finite(v[i])) {
        BlowUp b;
        b.step = s.step;
        b.time = s.time;
        b.module = "positions";
        b.message = "a non-finite position or velocity was written at point " + std::to_string(i) +
                    " (step " + std::to_string(s.step) +
                    "): the simulation does not step from it (write finite values, or reset())";
        throw BlowUpError(b);
      }
  }

  // Before control returns to Python: a blow-up that the simulator checks only at its
  // sampling cadence (a device backend's state, an energy that ran away within the last
  // steps) is raised now, not at some later call.
  // On the CPU, explicit schemes check every step (non-finite values, and the energy when the
  // kinetic bound rises: Simulator::check_health), so the full check is for a device backend
  // (which the simulator checks at its sampling cadence) and the implicit schemes (one force
  // evaluation beside a solve's many).
  void check_before_returning() {
    const bool worth = sim_->backend() || sim_->integrator().uses_jacobians();
    if (worth && energy_checked_at_ != sim_->steps_taken()) {
      energy_checked_at_ = sim_->steps_taken();
      if (!checked_energy()) throw BlowUpError(*sim_->blow_up());
    }
    warn_if_unconverged();
  }

  // Copies `from` into the state the views see (its buffers stay where they are) and makes it
  // the simulator's state through restore (which also clears a blow-up).
  void replace_state(const State& from, std::uint64_t frames) {
    State s = std::move(sim_->state_for_editing());
    std::copy(from.x().begin(), from.x().end(), s.x().begin());
    std::copy(from.v().begin(), from.v().end(), s.v().begin());
    std::copy(from.f().begin(), from.f().end(), s.f().begin());
    s.time = from.time;
    s.step = from.step;
    s.history = from.history;
    s.stage_memory = from.stage_memory;
    sim_->restore(std::move(s), frames);
    sync_for_python();
  }

  // The columns of stats.csv (for_each_stats_column, as StatsWriter writes them), by name, for
  // the last sample. Names are rewritten only when they change (stages plugged in later).
  void record(const EnergySample& e, const Profile& p) {
    std::size_t i = 0;
    for_each_stats_column(e, p, [&](std::string_view prefix, std::string_view name, auto value) {
      if (i == stats_.size()) stats_.emplace_back();
      StatColumn& c = stats_[i++];
      if (c.name.size() != prefix.size() + name.size() ||
          std::string_view(c.name).substr(0, prefix.size()) != prefix ||
          std::string_view(c.name).substr(prefix.size()) != name)
        c.name = std::string(prefix) + std::string(name);
      c.integer = std::is_integral_v<decltype(value)>;
      c.value = double(value);
      if constexpr (std::is_integral_v<decltype(value)>) c.count = value;
    });
    stats_.resize(i);
    ++stats_rows_;
  }

  // The energies' runaway check with the force array and the stages' memory put back, as
  // energies() does: asking never changes the trajectory. False with blow_up() set.
  bool checked_energy() {
    return keeping_forces([this] { return sim_->check_energy(); });
  }

  // `evaluate()` (energies evaluate the forces at the current state) with the force array and
  // the stages' memory put back afterwards, so that asking never changes the trajectory.
  template <class F>
  std::invoke_result_t<F&> keeping_forces(F&& evaluate) {
    State& s = state();
    const std::vector<Vec3> f(s.f().begin(), s.f().end());
    const std::vector<StageMemory> memory = s.stage_memory;
    const auto result = evaluate();
    State& after = state();
    std::copy(f.begin(), f.end(), after.f().begin());
    after.stage_memory = memory;
    return result;
  }

  // Once per simulation, a RuntimeWarning when an implicit step ended unconverged
  // (Simulator::unconverged: the force imbalance above its bound), naming the step and solver.
  void warn_if_unconverged() {
    if (warned_unconverged_ || !sim_->unconverged()) return;
    warned_unconverged_ = true;
    const std::string text = "maille: " + unconverged_text(*sim_);
    if (PyErr_WarnEx(PyExc_RuntimeWarning, text.c_str(), 1) != 0) throw py::error_already_set();
  }

  std::unique_ptr<Simulator> sim_;
  std::filesystem::path source_;  // the scene file; empty for a model built in code
  bool from_code_ = false;
  std::vector<std::string> code_settings_;  // the code model's own simulation.* / fields.* keys
  std::vector<std::string> sets_;           // overrides so far: construction, then live edits
  SimulationSettings loaded_;               // the settings as last read (before the simulator's)
  std::string name_;
  struct StatColumn {
    std::string name;
    bool integer = false;  // step and the counters
    double value = 0;
    std::uint64_t count = 0;  // when integer
  };
  std::vector<StatColumn> stats_;  // the last sample's stats.csv row
  std::uint64_t stats_rows_ = 0;
  bool capture_ = false;
  Snapshot captured_;
  std::atomic<bool> busy_{false};
  std::thread::id owner_ = std::this_thread::get_id();  // the thread that made it
  SignalPoll signals_;  // Python's signal handlers while stepping without the GIL
  std::uint64_t energy_checked_at_ = 0;
  bool warned_unconverged_ = false;
};

}  // namespace maille::python
