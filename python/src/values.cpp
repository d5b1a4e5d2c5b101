// Python values as TOML text. Overrides go through the scene reader exactly as `--set` does
// (src/scene/overrides.cpp), so a value set from Python is checked by the same code, with the
// same messages, as the same value in a scene file.
#include <cmath>
#include <cstdio>

#include "bindings.hpp"
#include "maille/link_registry.hpp"
#include "maille/stage_registry.hpp"

namespace maille::python {

void fail(const std::string& where, const std::string& key, const std::string& message) {
  throw SceneError(InputError{where, 0, 0, key, message});
}

namespace {

std::string quoted(const std::string& s) {
  std::string out = "\"";
  for (const char c : s) {
    switch (c) {
      case '"':
        out += "\\\"";
        break;
      case '\\':
        out += "\\\\";
        break;
      case '\n':
        out += "\\n";
        break;
      case '\t':
        out += "\\t";
        break;
      case '\r':
        out += "\\r";
        break;
      default:
        if (static_cast<unsigned char>(c) < 0x20) {
          char buf[8];
          std::snprintf(buf, sizeof buf, "\\u%04x", static_cast<unsigned>(c));
          out += buf;
        } else {
          out += c;
        }
    }
  }
  return out + "\"";
}

std::string real_text(double v) {
  if (std::isnan(v)) return "nan";
  if (std::isinf(v)) return v > 0 ? "inf" : "-inf";
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.17g", v);  // round-trips exactly
  return buf;
}

}  // namespace

std::string toml_value(const py::handle& value, const std::string& key) {
  if (py::isinstance<py::bool_>(value)) return value.cast<bool>() ? "true" : "false";
  if (py::isinstance<py::str>(value)) return quoted(value.cast<std::string>());
  // NumPy scalars and 0-d arrays first: np.bool_ is not a Python bool.
  if (py::hasattr(value, "dtype") && py::hasattr(value, "item") &&
      (!py::hasattr(value, "ndim") || value.attr("ndim").cast<int>() == 0))
    return toml_value(value.attr("item")(), key);
  if (PyLong_Check(value.ptr())) return py::str(value).cast<std::string>();
  if (PyFloat_Check(value.ptr())) return real_text(value.cast<double>());
  if (py::isinstance<py::dict>(value)) {
    std::string out = "{ ";
    bool first = true;
    for (const auto& [k, v] : value.cast<py::dict>()) {
      if (!first) out += ", ";
      first = false;
      const std::string name = py::str(k).cast<std::string>();
      out += quoted(name) + " = " + toml_value(v, key + "." + name);
    }
    return out + " }";
  }
  if (py::hasattr(value, "tolist")) return toml_value(value.attr("tolist")(), key);
  if (py::isinstance<py::sequence>(value)) {
    std::string out = "[";
    bool first = true;
    for (const auto& v : value.cast<py::sequence>()) {
      if (!first) out += ", ";
      first = false;
      out += toml_value(v, key);
    }
    return out + "]";
  }
  if (PyNumber_Check(value.ptr()))
    return real_text(py::float_(py::reinterpret_borrow<py::object>(value)).cast<double>());
  fail("<maille>", key,
       "cannot write a value of type " +
           py::str(value.get_type().attr("__name__")).cast<std::string>() +
           " as a scene value (numbers, booleans, strings, lists and dicts are)");
}

std::string override_text(const std::string& key, const py::handle& value) {
  return key + "=" + toml_value(value, key);
}

std::vector<std::string> overrides_from(const py::object& overrides) {
  std::vector<std::string> out;
  if (overrides.is_none()) return out;
  if (py::isinstance<py::dict>(overrides)) {
    for (const auto& [k, v] : overrides.cast<py::dict>())
      out.push_back(override_text(py::str(k).cast<std::string>(), v));
    return out;
  }
  if (py::isinstance<py::str>(overrides))
    fail("<maille.Simulation>", "overrides",
         "expected a dict {key: value} or a list of \"KEY=VALUE\" strings, got a string");
  for (const auto& item : overrides) {
    if (!py::isinstance<py::str>(item))
      fail("<maille.Simulation>", "overrides",
           "expected a dict {key: value} or a list of \"KEY=VALUE\" strings");
    out.push_back(item.cast<std::string>());
  }
  return out;
}

Scene settings_scene(const std::vector<std::string>& sets) {
  static const LinkKindRegistry kinds = LinkKindRegistry::with_builtins();
  static const StageRegistry stages = StageRegistry::with_builtins();
  return value_or_throw(
      parse_scene("[[mass]]\nposition = [0, 0, 0]\n", "<maille.Model>", kinds, stages, sets));
}

}  // namespace maille::python
