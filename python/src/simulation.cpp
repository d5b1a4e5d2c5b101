// maille.Simulation: a Simulator driven from Python.
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
#include <atomic>
#include <chrono>
#include <cmath>
#include <memory>
#include <optional>

#include "bindings.hpp"
#include "maille/checkpoint.hpp"
#include "maille/limits.hpp"

namespace maille::python {

namespace {

using Clock = std::chrono::steady_clock;

class Simulation {
 public:
  // From a scene file (with overrides), or from a model built in code.
  Simulation(const py::object& source, const py::object& overrides, const py::object& threads,
             const py::object& step, const py::object& integrator) {
    std::vector<std::string> sets = overrides_from(overrides);
    // Keyword settings as overrides, validated like the scene's own keys.
    if (!step.is_none()) sets.push_back(override_text("simulation.step", step));
    if (!integrator.is_none()) sets.push_back(override_text("simulation.integrator", integrator));
    if (!threads.is_none()) {
      const long long n = threads.cast<long long>();
      if (n < 1 || n > limits::max_threads)
        fail("<maille.Simulation>", "threads",
             "must be in [1, 1024] (got " + std::to_string(n) + ")");
      sets.push_back("simulation.threads=" + std::to_string(n));
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
      const py::object fspath = py::module_::import("os").attr("fspath")(source);
      source_ = fspath.cast<std::string>();
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
    sim_->on_publish([this](const Snapshot& s) {
      if (capture_) captured_ = s;
    });
  }

  // --- stepping ------------------------------------------------------------------------------

  std::uint64_t step(long long n) {
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
    const double h = sim_->settings().step;
    std::uint64_t total = 0;
    if (!steps.is_none()) {
      const long long s = steps.cast<long long>();
      if (s < 0 || double(s) > double(limits::max_steps))
        fail(where, "steps", "must be in [0, 1e12]");
      total = static_cast<std::uint64_t>(s);
    } else {
      const bool given = !duration.is_none();
      const double d = given ? duration.cast<double>() : duration_of_scene();
      if (!std::isfinite(d) || d < 0) fail(where, "duration", "must be a finite number >= 0");
      const double n = std::round(d / h);
      if (!(n <= double(limits::max_steps)))
        fail(where, "duration", "is more than 1e12 steps at this step size");
      const auto wanted = static_cast<std::uint64_t>(n);
      total = given ? wanted : (wanted > sim_->steps_taken() ? wanted - sim_->steps_taken() : 0);
    }
    long long k = every.is_none() ? sim_->settings().publish_every : every.cast<long long>();
    if (k < 1) fail(where, "every", "must be >= 1");
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
    State& s = state();
    Vec3* data = which == 0 ? s.x().data() : s.v().data();
    return py::array_t<Real>({static_cast<py::ssize_t>(s.size()), py::ssize_t{3}},
                             {py::ssize_t(sizeof(Vec3)), py::ssize_t(sizeof(Real))},
                             reinterpret_cast<Real*>(data), self);
  }

  py::dict energies() {
    Busy busy(*this);
    // Energies evaluate the forces at the current state: the force array and the stages' memory
    // are put back afterwards, so that asking never changes the trajectory.
    State& s = state();
    const std::vector<Vec3> f(s.f().begin(), s.f().end());
    const std::vector<StageMemory> memory = s.stage_memory;
    const Energies e = sim_->energies();
    State& after = state();
    std::copy(f.begin(), f.end(), after.f().begin());
    after.stage_memory = memory;
    py::dict d;
    d["kinetic"] = e.kinetic;
    d["elastic"] = e.elastic;
    d["gravity"] = e.gravity;
    d["total"] = e.total();
    return d;
  }

  py::dict stats() const {
    // Step and counters are integers in stats.csv: ints here too.
    py::dict d;
    for (std::size_t i = 0; i < stat_names_.size(); ++i) {
      const bool integer = i == 1 || (i >= 6 + stages_ && i < 6 + stages_ + counters_);
      if (integer)
        d[py::str(stat_names_[i])] = static_cast<std::uint64_t>(stat_values_[i]);
      else
        d[py::str(stat_names_[i])] = stat_values_[i];
    }
    return d;
  }

  // --- live edits ----------------------------------------------------------------------------

  void set(const std::string& key, const py::object& value) {
    Busy busy(*this);
    std::vector<std::string> sets = sets_;
    sets.push_back(override_text(key, value));
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
    const std::string changed = fixed_setting_changed(loaded_, scene.settings);
    if (!changed.empty())
      fail("--set", key,
           "simulation." + changed +
               " cannot change while the simulation runs: give it in overrides= when making "
               "the Simulation (live: simulation.step, simulation.integrator, "
               "simulation.implicit.*, simulation.duration, fields, links' and builders' "
               "parameters)");
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
      // [simulation.implicit] before the scheme: a switch to implicit_euler builds it with them.
      if (!(scene.settings.implicit == sim_->settings().implicit))
        sim_->set_implicit(scene.settings.implicit);
      if (scene.settings.integrator != sim_->settings().integrator)
        sim_->set_integrator(scene.settings.integrator);
      if (scene.settings.step != sim_->settings().step) sim_->set_step(scene.settings.step);
    } catch (const std::invalid_argument& e) {
      fail("--set", key, e.what());
    }
    loaded_ = scene.settings;
    sets_ = std::move(sets);
    sync_for_python();
  }

  // --- checkpoints ---------------------------------------------------------------------------

  void save_checkpoint(const std::string& path) {
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

  void load_checkpoint(const std::string& path) {
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
    stat_names_.clear();
    stat_values_.clear();
    stats_rows_ = 0;
  }

  // --- rendering -----------------------------------------------------------------------------

  void render(const std::string& path, int width, int height, const py::object& camera, int samples,
              bool mesh) {
    const std::string where = "<maille.Simulation.render>";
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
    o.width = width;
    o.height = height;
    o.samples = samples;
    o.mesh = mesh;
    if (!camera.is_none()) {
      const auto c = camera.cast<std::vector<double>>();
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
  std::uint64_t hash() { return state_hash(state()); }

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

  std::uint64_t advance(std::uint64_t n) {
    std::uint64_t done = 0;
    bool fine = true;
    {
      py::gil_scoped_release release;
      auto last = Clock::now();
      while (done < n) {
        if (!sim_->step()) {
          fine = false;
          break;
        }
        ++done;
        if ((done & 15) == 0 && Clock::now() - last > std::chrono::milliseconds(100)) {
          last = Clock::now();
          py::gil_scoped_acquire acquire;
          if (PyErr_CheckSignals() != 0) {
            sync_for_python();
            throw py::error_already_set();
          }
        }
      }
    }
    sync_for_python();
    if (!fine) {
      if (sim_->blow_up()) throw BlowUpError(*sim_->blow_up());
      throw std::runtime_error("the simulation stopped");
    }
    return done;
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

  // The columns of stats.csv (StatsWriter::write), by name, for the last sample.
  void record(const EnergySample& e, const Profile& p) {
    stages_ = p.stages().size();
    counters_ = p.counters().size();
    const std::size_t columns = 6 + stages_ + counters_ + p.gauges().size();
    stat_names_.resize(columns);
    stat_values_.resize(columns);
    std::size_t i = 0;
    auto put = [&](const std::string& name, double v) {
      if (stat_names_[i] != name) stat_names_[i] = name;
      stat_values_[i++] = v;
    };
    put("time", e.time);
    put("step", double(e.step));
    put("kinetic", e.energies.kinetic);
    put("elastic", e.energies.elastic);
    put("gravity", e.energies.gravity);
    put("total", e.energies.total());
    for (const auto& s : p.stages()) put("ns_" + s.name, s.last_ns);
    for (const auto& c : p.counters()) put(c.name, double(c.last));
    for (const auto& g : p.gauges()) put(g.name, g.last);
    ++stats_rows_;
  }

  // The settings a live edit may not change (the simulator was built with them).
  static std::string fixed_setting_changed(const SimulationSettings& a,
                                           const SimulationSettings& b) {
    if (a.publish_every != b.publish_every) return "output_every";
    if (a.sample_every != b.sample_every) return "sample_every";
    if (a.threads != b.threads) return "threads";
    if (a.runaway_factor != b.runaway_factor) return "runaway_factor";
    if (a.backend != b.backend) return "backend";
    if (a.backend_options.device != b.backend_options.device) return "gpu_device";
    return {};
  }

  std::unique_ptr<Simulator> sim_;
  std::filesystem::path source_;  // the scene file; empty for a model built in code
  bool from_code_ = false;
  std::vector<std::string> code_settings_;  // the code model's own simulation.* / fields.* keys
  std::vector<std::string> sets_;           // overrides so far: construction, then live edits
  SimulationSettings loaded_;               // the settings as last read (before the simulator's)
  std::string name_;
  std::vector<std::string> stat_names_;
  std::vector<double> stat_values_;
  std::size_t stages_ = 0, counters_ = 0;  // columns of each in the last sample
  std::uint64_t stats_rows_ = 0;
  bool capture_ = false;
  Snapshot captured_;
  std::atomic<bool> busy_{false};
};

}  // namespace

void bind_simulation(py::module_& mod) {
  auto cls = py::class_<Simulation>(mod, "Simulation",
                                    R"(A simulation of a scene file or of a maille.Model.

Simulation(path_or_model, overrides=None, threads=None, step=None, integrator=None)

overrides: {key: value} (or ["KEY=VALUE", ...]) applied to the scene as `--set` does;
threads, step and integrator are the keys simulation.threads, simulation.step and
simulation.integrator. Errors raise maille.SceneError (file, line, column, key).)");
  cls.def(py::init<const py::object&, const py::object&, const py::object&, const py::object&,
                   const py::object&>(),
          py::arg("source"), py::arg("overrides") = py::none(), py::kw_only(),
          py::arg("threads") = py::none(), py::arg("step") = py::none(),
          py::arg("integrator") = py::none());
  cls.def("step", &Simulation::step, py::arg("n") = 1,
          "Advances n steps (GIL released). Raises maille.BlowUp on a numerical blow-up. Returns "
          "the steps taken.");
  cls.def(
      "run",
      [](py::object self, const py::object& duration, const py::object& steps,
         const py::object& every, const py::object& callback) {
        return self.cast<Simulation&>().run(duration, steps, every, callback, self);
      },
      py::arg("duration") = py::none(), py::kw_only(), py::arg("steps") = py::none(),
      py::arg("every") = py::none(), py::arg("callback") = py::none(),
      "run(duration=None, *, steps=None, every=None, callback=None): advances `duration` "
      "seconds (or `steps` steps; neither: until the scene's duration, from t = 0, as `maille "
      "run`), calling callback(sim) after every `every` steps (default: the scene's "
      "output_every); a callback returning False stops the run. Returns the steps taken.");
  cls.def_property_readonly(
      "positions", [](py::object self) { return self.cast<Simulation&>().view(0, self); },
      "(n, 3) float64 view of the positions (m): the engine's memory, writable.");
  cls.def_property_readonly(
      "velocities", [](py::object self) { return self.cast<Simulation&>().view(1, self); },
      "(n, 3) float64 view of the velocities (m/s): the engine's memory, writable. Under "
      "leapfrog they are the staggered v(t - h/2) once stepping started (velocity_time).");
  cls.def_property_readonly(
      "time", [](Simulation& s) { return s.sim().time(); }, "s");
  cls.def_property_readonly("steps", [](Simulation& s) { return s.sim().steps_taken(); });
  cls.def_property_readonly(
      "step_size", [](Simulation& s) { return s.sim().settings().step; }, "h, s");
  cls.def_property_readonly("point_count",
                            [](Simulation& s) { return s.sim().model().points.size(); });
  cls.def_property_readonly("link_count",
                            [](Simulation& s) { return s.sim().model().links.total(); });
  cls.def_property_readonly("integrator",
                            [](Simulation& s) { return s.sim().settings().integrator; });
  cls.def_property_readonly("threads", [](Simulation& s) { return s.sim().threads(); });
  cls.def_property_readonly("name", &Simulation::name);
  cls.def_property_readonly("duration", &Simulation::duration_of_scene,
                            "the scene's duration (s), what run() without arguments reaches");
  cls.def_property_readonly(
      "velocity_time", &Simulation::velocity_time,
      "'synchronous' (v at the time of x) or 'half_step' (leapfrog's v(t - h/2))");
  cls.def_property_readonly(
      "stable_step", [](Simulation& s) { return s.sim().stability().max_step; },
      "the scheme's stability estimate for this model (s)");
  cls.def_property_readonly(
      "groups", [](Simulation& s) { return model_groups(s.sim().model()); },
      "dict: group name -> NumPy index array of its points");
  cls.def_property_readonly(
      "masses",
      [](Simulation& s) {
        const auto& m = s.sim().model().points.mass;
        py::array_t<Real> out(static_cast<py::ssize_t>(m.size()));
        std::copy(m.begin(), m.end(), out.mutable_data());
        return out;
      },
      "masses (kg), a copy");
  cls.def_property_readonly(
      "fixed",
      [](Simulation& s) {
        const auto& k = s.sim().model().points.kind;
        py::array_t<bool> out(static_cast<py::ssize_t>(k.size()));
        for (std::size_t i = 0; i < k.size(); ++i) out.mutable_data()[i] = k[i] != PointKind::free;
        return out;
      },
      "True for fixed and driven points, a copy");
  cls.def("energies", &Simulation::energies,
          "dict: kinetic, elastic, gravity, total (J) of the current state (synchronised "
          "velocities)");
  cls.def("stats", &Simulation::stats,
          "dict of the last stats.csv row's columns (empty before the first sample)");
  cls.def(
      "set", &Simulation::set, py::arg("key"), py::arg("value"),
      "Live edit of a scene key, validated like --set; raises maille.SceneError naming the key");
  cls.def("save_checkpoint", &Simulation::save_checkpoint, py::arg("path"));
  cls.def("load_checkpoint", &Simulation::load_checkpoint, py::arg("path"));
  cls.def("reset", &Simulation::reset, "Back to the initial state (t = 0).");
  cls.def("state_hash", &Simulation::hash,
          "64-bit hash of positions, velocities, time, step, the scheme's history and the stages' "
          "memory: equal hashes, bit-identical states");
  cls.def("render", &Simulation::render, py::arg("path"), py::kw_only(), py::arg("width") = 1280,
          py::arg("height") = 720, py::arg("camera") = py::none(), py::arg("samples") = 4,
          py::arg("mesh") = false,
          "A PNG of the current state, headless, framed like `maille render`'s last frame; "
          "camera=(yaw, pitch[, zoom]) in degrees.");
  cls.def("__repr__", [](Simulation& s) {
    return "<maille.Simulation '" + s.name() +
           "': " + std::to_string(s.sim().model().points.size()) +
           " points, t = " + std::to_string(s.sim().time()) + " s>";
  });
}

}  // namespace maille::python
