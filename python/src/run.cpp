// maille.run(): a scene file run as `maille run` runs it (maille/scene_run.hpp: the same
// SceneRun), into a folder of frames, stats.csv and checkpoints; returns the run's summary.
//
// The GIL is released for the run and taken back every 0.1 s to run Python's signal handlers
// (SignalPoll): Ctrl-C ends the run between two steps (or abandons a long implicit step) with
// its files complete, then raises KeyboardInterrupt. Warnings (a step beyond the stability
// estimate, the stages' doubts, a cloth crossing itself) are Python warnings, given when the run
// ends.
#include <cmath>

#include "bindings.hpp"
#include "maille/limits.hpp"
#include "maille/scene_run.hpp"
#include "signal_poll.hpp"

namespace maille::python {

namespace {

SceneRunOptions run_options(const py::object& source, const py::object& overrides,
                            const py::object& out, const py::object& steps,
                            const py::object& duration, const py::object& threads,
                            const py::object& frames, const py::object& format,
                            const py::object& every, const py::object& checkpoint_every) {
  const std::string where = "<maille.run>";
  SceneRunOptions o;
  o.scene = path_arg(source, where, "source");
  o.sets = overrides_from(overrides);
  if (!out.is_none()) o.out = path_arg(out, where, "out");
  if (!steps.is_none()) {
    const long long s = int_arg(steps, where, "steps");
    if (s < 0 || double(s) > double(limits::max_steps))
      fail(where, "steps", "must be in [0, 1e12]");
    o.steps = static_cast<std::uint64_t>(s);
  }
  if (!duration.is_none()) {
    const double d = real_arg(duration, where, "duration");
    if (!std::isfinite(d) || d < 0) fail(where, "duration", "must be a finite number >= 0");
    o.duration = d;
    o.duration_name = "duration";
  }
  if (!threads.is_none()) {
    const long long n = int_arg(threads, where, "threads");
    if (n < 1 || n > limits::max_threads)
      fail(where, "threads", "must be in [1, 1024] (got " + std::to_string(n) + ")");
    o.threads = int(n);
  }
  o.frames = bool_arg(frames, where, "frames");
  const std::string name = str_of(format, where, "format");
  const auto parsed = parse_frame_format(name);
  if (!parsed)
    fail(where, "format", "must be one of " + name_list<FrameFormat>() + " (got '" + name + "')");
  o.format = *parsed;
  if (!every.is_none()) {
    const long long k = int_arg(every, where, "every");
    if (k < 1 || k > kNeverEvery) fail(where, "every", "must be in [1, 2^30]");
    o.every = int(k);
  }
  if (!checkpoint_every.is_none()) {
    const long long k = int_arg(checkpoint_every, where, "checkpoint_every");
    if (k < 1) fail(where, "checkpoint_every", "must be >= 1");
    o.checkpoint_every = static_cast<std::uint64_t>(k);
  }
  return o;
}

// The run's outcome as Python sees it: the summary, or the exception of its exit code.
py::dict outcome(const SceneRun& run, const std::string& source) {
  const SceneRunReport& r = run.report();
  switch (r.exit) {
    case exit_code::ok:
      break;
    case exit_code::bad_input:
      throw SceneError(r.input ? *r.input : InputError{source, 0, 0, "", r.error});
    case exit_code::usage:
      throw SceneError(InputError{"<maille.run>", 0, 0, "duration", r.error});
    case exit_code::blow_up: {
      BlowUp b;
      if (r.blow_up)
        b = *r.blow_up;
      else
        b.message = r.error;
      throw BlowUpError(b);
    }
    case exit_code::interrupted:
      PyErr_SetString(PyExc_KeyboardInterrupt, "maille.run: interrupted");
      throw py::error_already_set();
    default:  // output_error
      PyErr_SetString(PyExc_OSError, r.error.c_str());
      throw py::error_already_set();
  }
  py::dict energies;
  for_each_energy(*r.energies, [&](const char* name, double value) { energies[name] = value; });
  py::dict d;
  d["name"] = run.scene().name;
  d["out"] = run.out().string();
  d["steps"] = r.steps_run;
  d["time"] = r.simulated;
  d["frames"] = r.frames;
  d["stats_rows"] = r.stats_rows;
  d["wall_seconds"] = r.wall;
  d["energies"] = energies;
  return d;
}

py::dict run(const py::object& source, const py::object& overrides, const py::object& out,
             const py::object& steps, const py::object& duration, const py::object& threads,
             const py::object& frames, const py::object& format, const py::object& every,
             const py::object& checkpoint_every) {
  SceneRunOptions o = run_options(source, overrides, out, steps, duration, threads, frames, format,
                                  every, checkpoint_every);
  const std::string scene = o.scene.string();
  SceneRun run(std::move(o));
  if (!run.load()) return outcome(run, scene);
  SignalPoll signals;
  std::vector<std::string> warnings;  // said once the GIL is back
  SceneRunHooks hooks;
  hooks.stop = [&signals] { return signals.pending(); };
  hooks.warn = [&warnings](const std::string& w) { warnings.push_back(w); };
  signals.start();
  {
    py::gil_scoped_release released;
    run.run(hooks);
  }
  for (const std::string& w : warnings)
    if (PyErr_WarnEx(PyExc_UserWarning, ("maille: " + w).c_str(), 1) != 0)
      throw py::error_already_set();
  if (!run.report().unconverged.empty() &&
      PyErr_WarnEx(PyExc_RuntimeWarning, ("maille: " + run.report().unconverged).c_str(), 1) != 0)
    throw py::error_already_set();
  signals.raise_if_pending();  // KeyboardInterrupt, the files complete
  return outcome(run, scene);
}

}  // namespace

void bind_run(py::module_& m) {
  m.def("run", &run, py::arg("source"), py::arg("overrides") = py::none(), py::kw_only(),
        py::arg("out") = py::none(), py::arg("steps") = py::none(),
        py::arg("duration") = py::none(), py::arg("threads") = py::none(),
        py::arg("frames") = py::bool_(true), py::arg("format") = py::str("ply"),
        py::arg("every") = py::none(), py::arg("checkpoint_every") = py::none(),
        R"(Runs a scene file as `maille run` does (the same code): frames, stats.csv and checkpoints
into `out` (default out/<scene name>).

run(source, overrides=None, *, out=None, steps=None, duration=None, threads=None, frames=True,
    format="ply", every=None, checkpoint_every=None) -> dict

overrides as in Simulation (`--set`); steps or duration (s) counted from t = 0 (neither: the
scene's duration); frames=False is --no-frames; every: steps between frames (the scene's
output_every); checkpoint_every: steps between out/checkpoint.bin. Returns {name, out, steps,
time, frames, stats_rows, wall_seconds, energies}. Raises maille.SceneError (a refused scene or
argument), maille.BlowUp (the files up to it complete), OSError (an output that cannot be
written), KeyboardInterrupt (Ctrl-C: the files written so far complete).)");
}

}  // namespace maille::python
