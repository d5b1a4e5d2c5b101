// maille.Simulation's Python binding: methods, arguments and docstrings (the class:
// simulation.hpp).
#include "simulation.hpp"

namespace maille::python {

namespace {

// A read-only property read from the simulator under the simulation's lock (Simulation::read):
// get(simulator), then the docstring if any.
template <class Get, class... Doc>
void simulator_property(py::class_<Simulation>& cls, const char* name, Get get, const Doc&... doc) {
  cls.def_property_readonly(
      name, [get](Simulation& s) { return s.read(get); }, doc...);
}

// A per-point array as a new NumPy array of T, each value through `f`.
template <class T, class Values, class F>
py::array_t<T> copy_of(const Values& values, F f) {
  py::array_t<T> out(static_cast<py::ssize_t>(values.size()));
  for (std::size_t i = 0; i < values.size(); ++i) out.mutable_data()[i] = f(values[i]);
  return out;
}

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
  cls.def("step", &Simulation::step, py::arg("n") = py::int_(1),
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
  simulator_property(
      cls, "time", [](const Simulator& m) { return m.time(); }, "s");
  simulator_property(cls, "steps", [](const Simulator& m) { return m.steps_taken(); });
  simulator_property(
      cls, "step_size", [](const Simulator& m) { return m.settings().step; }, "h, s");
  simulator_property(cls, "point_count",
                     [](const Simulator& m) { return m.model().points.size(); });
  simulator_property(cls, "link_count", [](const Simulator& m) { return m.model().links.total(); });
  simulator_property(cls, "integrator", [](const Simulator& m) { return m.settings().integrator; });
  simulator_property(cls, "threads", [](const Simulator& m) { return m.threads(); });
  cls.def_property_readonly("name", &Simulation::name);
  cls.def_property_readonly(
      "duration",
      [](Simulation& s) { return s.read([&](const Simulator&) { return s.duration_of_scene(); }); },
      "the scene's duration (s), what run() without arguments reaches");
  cls.def_property_readonly(
      "overrides", &Simulation::overrides,
      "the overrides applied, as \"KEY=VALUE\" strings: construction's, then live edits, one "
      "per key (its latest value)");
  cls.def_property_readonly(
      "velocity_time",
      [](Simulation& s) { return s.read([&](const Simulator&) { return s.velocity_time(); }); },
      "'synchronous' (v at the time of x) or 'half_step' (leapfrog's v(t - h/2))");
  simulator_property(
      cls, "stable_step", [](const Simulator& m) { return m.stability().max_step; },
      "the scheme's stability estimate for this model (s)");
  simulator_property(
      cls, "groups", [](const Simulator& m) { return model_groups(m.model()); },
      "dict: group name -> NumPy index array of its points");
  simulator_property(
      cls, "masses",
      [](const Simulator& sim) {
        return copy_of<Real>(sim.model().points.mass, [](Real m) { return m; });
      },
      "masses (kg), a copy");
  simulator_property(
      cls, "fixed",
      [](const Simulator& sim) {
        return copy_of<bool>(sim.model().points.kind,
                             [](PointKind k) { return k != PointKind::free; });
      },
      "True for fixed and driven points, a copy");
  cls.def("energies", &Simulation::energies,
          "dict: kinetic, elastic, gravity, contact, total (J) of the current state "
          "(synchronised velocities; contact: conditional links and the stages' contacts)");
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
  cls.def("render", &Simulation::render, py::arg("path"), py::kw_only(),
          py::arg("width") = py::int_(1280), py::arg("height") = py::int_(720),
          py::arg("camera") = py::none(), py::arg("samples") = py::int_(4),
          py::arg("mesh") = py::bool_(false),
          "A PNG of the current state, headless, framed like `maille render`'s last frame; "
          "camera=(yaw, pitch[, zoom]) in degrees.");
  cls.def("__repr__", [](Simulation& s) {
    return s.read([&](const Simulator& m) {
      return "<maille.Simulation '" + s.name() + "': " + std::to_string(m.model().points.size()) +
             " points, t = " + std::to_string(m.time()) + " s>";
    });
  });
}

}  // namespace maille::python
