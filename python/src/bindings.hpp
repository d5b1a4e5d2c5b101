// The Python module's shared declarations: the errors it raises, scene values written as TOML,
// the model built in code and the simulation. docs/python.md documents the API.
#pragma once

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <exception>
#include <filesystem>
#include <string>
#include <vector>

#include "maille/model.hpp"
#include "maille/result.hpp"
#include "maille/scene.hpp"
#include "maille/simulator.hpp"
#include "maille/snapshot.hpp"

namespace maille::python {

namespace py = pybind11;

// Thrown by the bindings, turned into the Python classes of the same names by the module's
// translator (module.cpp): maille.SceneError (file, line, column, key), maille.BlowUp (step,
// time, module = kind), maille.CheckpointError (file, key).
struct SceneError : std::exception {
  explicit SceneError(InputError e) : error(std::move(e)), text(error.to_string()) {}
  const char* what() const noexcept override { return text.c_str(); }
  InputError error;
  std::string text;
};
struct CheckpointError : SceneError {
  using SceneError::SceneError;
};
struct BlowUpError : std::exception {
  explicit BlowUpError(BlowUp b) : info(std::move(b)) {}
  const char* what() const noexcept override { return info.message.c_str(); }
  BlowUp info;
};

// An error in an argument of a call, raised as maille.SceneError with `file` naming the call
// ("<maille.Model.add_link>") and `key` the argument.
[[noreturn]] void fail(const std::string& where, const std::string& key,
                       const std::string& message);

// Arguments read with errors that name them: a wrong type raises TypeError ("<maille.X>:
// argument 'n' must be an int (got str)"), a wrong value SceneError (file the call, key the
// argument). Paths accept str and os.PathLike and refuse an empty path or a NUL character.
std::string str_of(const py::handle& value, const std::string& where, const std::string& key);
std::string path_arg(const py::handle& value, const std::string& where, const std::string& key);
long long int_arg(const py::handle& value, const std::string& where, const std::string& key);
double real_arg(const py::handle& value, const std::string& where, const std::string& key);
bool bool_arg(const py::handle& value, const std::string& where, const std::string& key);
// A scene key path as `--set` takes it (table.key, table[0].key), else SceneError.
std::string key_arg(const py::handle& value, const std::string& where, const std::string& what);

// A Python value as TOML text, for `--set`-style overrides: bool, int, float (and NumPy
// scalars), str, sequences (lists, tuples, arrays) and dicts (inline tables).
std::string toml_value(const py::handle& value, const std::string& key);
// "key=value" in the form of `--set`.
std::string override_text(const std::string& key, const py::handle& value);
// Overrides given as a dict {key: value} or as a list of "KEY=VALUE" strings.
std::vector<std::string> overrides_from(const py::object& overrides);
// Appends an override, dropping an earlier one of the same key (the later value wins anyway):
// the list holds one entry per key, however many live edits were made.
void merge_override(std::vector<std::string>& sets, std::string text);

// A model built in code: the C++ model (points and links in the order they were added) and
// the overrides of `simulation.*` and `fields.*` keys set on it (validated when set).
struct CodeModel {
  Model model;
  std::vector<std::string> settings;
};

// The settings and fields of a code model: a scene of one point read with `sets` applied, so
// that the keys are validated as in a file and default as in a file (gravity -9.81 along y).
// Throws SceneError.
Scene settings_scene(const std::vector<std::string>& sets);

// Rethrows a scene reader's error as SceneError.
template <class T>
T value_or_throw(Result<T> r) {
  if (!r) throw SceneError(r.error());
  return std::move(r.value());
}

// A PNG of one snapshot of a model, framed and lit like `maille render`'s last frame
// (render_still.cpp). Throws std::runtime_error when the module was built without rendering or
// when the OpenGL context or the file fails.
struct StillOptions {
  int width = 1280, height = 720;  // pixels
  int samples = 4;                 // multisampling
  double yaw = 25, pitch = 15, zoom = 1;
  bool mesh = false;  // also the links inside cloth surfaces
};
bool render_available();
void render_still(const Model& model, const Snapshot& snapshot, const std::filesystem::path& file,
                  const StillOptions& options);

// dict: group name -> NumPy index array of its points.
py::dict model_groups(const Model& m);

void bind_model(py::module_& m);
void bind_simulation(py::module_& m);
void bind_run(py::module_& m);  // maille.run(): a scene file run as `maille run` runs it

}  // namespace maille::python
