// The module `maille`: its exception classes, the translation of the engine's errors into them,
// the two classes (Model, Simulation) and run().
#include <pybind11/eval.h>

#include "bindings.hpp"
#ifdef MAILLE_WITH_RENDER
#include "maille/gpu.hpp"
#endif

namespace maille::python {

namespace {

// Defined in Python so that they carry plain attributes and pickle like any exception.
constexpr const char* kExceptions = R"(
class Error(Exception):
    """Base class of the errors maille raises."""


class SceneError(Error, ValueError):
    """A scene, an override or an argument was refused.

    file, line, column: where (line 0 when not tied to a line: an override names "--set",
    an argument "<maille.Model.add_link>" and the like); key: the offending key's dotted path
    ("flag[0].stiffness"); message: what is wrong. str(e) is the command line's message.
    """

    def __init__(self, text, file="", line=0, column=0, key="", message=""):
        super().__init__(text)
        self.file = file
        self.line = line
        self.column = column
        self.key = key
        self.message = message or text


class CheckpointError(SceneError):
    """A checkpoint could not be read or belongs to another model or scheme."""


class BlowUp(Error, RuntimeError):
    """The simulation blew up: step, time (s) and kind (the brick kind or stage where it
    started, e.g. "spring_damper"; also as `module`); str(e) is the full report."""

    def __init__(self, message, step=0, time=0.0, kind=""):
        super().__init__(message)
        self.message = message
        self.step = step
        self.time = time
        self.kind = kind
        self.module = kind
)";

// Handles, not objects: they are never released (no decref after the interpreter finalised).
py::handle g_scene_error, g_checkpoint_error, g_blow_up;

void raise_input(py::handle cls, const InputError& e) {
  const py::object exc =
      cls(e.to_string(), py::arg("file") = e.file, py::arg("line") = e.line,
          py::arg("column") = e.column, py::arg("key") = e.key, py::arg("message") = e.message);
  PyErr_SetObject(cls.ptr(), exc.ptr());
}

}  // namespace

}  // namespace maille::python

PYBIND11_MODULE(_maille, m) {
  namespace py = pybind11;
  using namespace maille::python;
  m.doc() =
      "Maille, a mass-interaction (mass-spring) physics engine: scenes, simulations and models "
      "built in code, with positions and velocities as NumPy views of the engine's memory. "
      "docs/python.md documents the API.";
  py::exec(kExceptions, m.attr("__dict__"));
  // Kept for the life of the process (the translator may run at interpreter shutdown).
  g_scene_error = py::object(m.attr("SceneError")).release();
  g_checkpoint_error = py::object(m.attr("CheckpointError")).release();
  g_blow_up = py::object(m.attr("BlowUp")).release();
  py::register_exception_translator([](std::exception_ptr p) {
    try {
      if (p) std::rethrow_exception(p);
    } catch (const CheckpointError& e) {
      raise_input(g_checkpoint_error, e.error);
    } catch (const SceneError& e) {
      raise_input(g_scene_error, e.error);
    } catch (const BlowUpError& e) {
      const py::object exc =
          g_blow_up(e.info.message, py::arg("step") = e.info.step, py::arg("time") = e.info.time,
                    py::arg("kind") = e.info.module);
      PyErr_SetObject(g_blow_up.ptr(), exc.ptr());
    }
  });
#ifdef MAILLE_WITH_RENDER
  maille::gpu::register_backend();  // `simulation.backend = "gpu"` as in `maille run`
#endif
  bind_model(m);
  bind_simulation(m);
  bind_run(m);
  m.attr("__version__") = MAILLE_VERSION;
  m.attr("render_available") = render_available();
#ifdef MAILLE_SINGLE_PRECISION
  m.attr("real") = "float32";
#else
  m.attr("real") = "float64";
#endif
}
