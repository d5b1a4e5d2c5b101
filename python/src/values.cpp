// Python values as TOML text. Overrides go through the scene reader exactly as `--set` does
// (src/scene/overrides.cpp), so a value set from Python is checked by the same code, with the
// same messages, as the same value in a scene file.
#include <algorithm>
#include <cctype>
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

namespace {

// Beyond this, a value is refused rather than recursed into (a list that contains itself
// would otherwise overflow the C stack): no scene key nests more than a few levels.
constexpr int kMaxDepth = 32;

std::string type_name(const py::handle& value) {
  return py::str(value.get_type().attr("__name__")).cast<std::string>();
}

// As large as a scene file may be: a value built of shared parts (x = [x, x] thirty times)
// is refused before it is written out in full.
constexpr std::size_t kMaxText = std::size_t{64} << 20;

struct Walk {
  std::vector<PyObject*> path;  // the containers being written, outermost first
  std::size_t nodes = 0;
};

std::string toml_at(const py::handle& value, const std::string& key, int depth, Walk& walk);

// Containers: refused when they contain themselves, nest too deep or grow too large.
struct Enter {
  Enter(const py::handle& value, const std::string& key, int depth, Walk& walk) : walk_(walk) {
    if (std::find(walk.path.begin(), walk.path.end(), value.ptr()) != walk.path.end())
      fail("<maille>", key, "the value contains itself: it cannot be written as a scene value");
    if (depth > kMaxDepth)
      fail("<maille>", key,
           "the value nests deeper than " + std::to_string(kMaxDepth) +
               " levels: scene values are numbers, booleans, strings and lists or tables of "
               "them");
    walk.path.push_back(value.ptr());
  }
  ~Enter() { walk_.path.pop_back(); }
  Enter(const Enter&) = delete;
  Enter& operator=(const Enter&) = delete;

 private:
  Walk& walk_;
};

void grow(std::string& out, const std::string& part, const std::string& key, Walk& walk) {
  out += part;
  if (out.size() > kMaxText || ++walk.nodes > kMaxText / 2)
    fail("<maille>", key, "the value is larger than a scene file may be (64 MiB)");
}

std::string toml_at(const py::handle& value, const std::string& key, int depth, Walk& walk) {
  if (py::isinstance<py::bool_>(value)) return value.cast<bool>() ? "true" : "false";
  if (py::isinstance<py::str>(value)) return quoted(str_of(value, "<maille>", key));
  // NumPy scalars and 0-d arrays first: np.bool_ is not a Python bool.
  if (py::hasattr(value, "dtype") && py::hasattr(value, "item") &&
      (!py::hasattr(value, "ndim") || value.attr("ndim").cast<int>() == 0))
    return toml_at(value.attr("item")(), key, depth + 1, walk);
  if (PyLong_Check(value.ptr())) return py::str(value).cast<std::string>();
  if (PyFloat_Check(value.ptr())) return real_text(value.cast<double>());
  if (py::isinstance<py::dict>(value)) {
    const Enter in(value, key, depth, walk);
    std::string out = "{ ";
    bool first = true;
    for (const auto& [k, v] : value.cast<py::dict>()) {
      if (!first) out += ", ";
      first = false;
      if (!py::isinstance<py::str>(k))
        fail("<maille>", key, "a table's keys must be strings (got " + type_name(k) + ")");
      const std::string name = str_of(k, "<maille>", key);
      grow(out, quoted(name) + " = " + toml_at(v, key + "." + name, depth + 1, walk), key, walk);
    }
    return out + " }";
  }
  if (py::hasattr(value, "tolist")) {
    const Enter in(value, key, depth, walk);
    return toml_at(value.attr("tolist")(), key, depth + 1, walk);
  }
  if (py::isinstance<py::sequence>(value) && !py::isinstance<py::bytes>(value)) {
    const Enter in(value, key, depth, walk);
    std::string out = "[";
    bool first = true;
    for (const auto& v : value.cast<py::sequence>()) {
      if (!first) out += ", ";
      first = false;
      grow(out, toml_at(v, key, depth + 1, walk), key, walk);
    }
    return out + "]";
  }
  if (PyNumber_Check(value.ptr()) && !py::isinstance<py::bytes>(value)) {
    double v = 0;
    try {
      v = py::float_(py::reinterpret_borrow<py::object>(value)).cast<double>();
    } catch (const py::error_already_set&) {
      fail("<maille>", key, "cannot read a value of type " + type_name(value) + " as a number");
    }
    return real_text(v);
  }
  fail("<maille>", key,
       "cannot write a value of type " + type_name(value) +
           " as a scene value (numbers, booleans, strings, lists and dicts are)");
}

}  // namespace

std::string str_of(const py::handle& value, const std::string& where, const std::string& key) {
  if (!py::isinstance<py::str>(value))
    throw py::type_error(where + ": argument '" + key + "' must be a str (got " + type_name(value) +
                         ")");
  Py_ssize_t size = 0;
  const char* text = PyUnicode_AsUTF8AndSize(value.ptr(), &size);
  if (!text) {  // a lone surrogate: not encodable as UTF-8
    PyErr_Clear();
    fail(where, key, "the text cannot be encoded as UTF-8");
  }
  return std::string(text, std::size_t(size));
}

std::string toml_value(const py::handle& value, const std::string& key) {
  Walk walk;
  return toml_at(value, key, 0, walk);
}

std::string path_arg(const py::handle& value, const std::string& where, const std::string& key) {
  if (!py::isinstance<py::str>(value) && !py::hasattr(value, "__fspath__"))
    throw py::type_error(where + ": argument '" + key +
                         "' must be a path (str or os.PathLike), got " + type_name(value));
  py::object path;
  try {
    path = py::module_::import("os").attr("fsdecode")(value);
  } catch (py::error_already_set& e) {
    if (!e.matches(PyExc_TypeError)) throw;
    throw py::type_error(where + ": argument '" + key +
                         "' must be a path (str or os.PathLike), got " + type_name(value));
  }
  const std::string text = str_of(path, where, key);
  if (text.empty()) fail(where, key, "the path is empty");
  if (text.find('\0') != std::string::npos) fail(where, key, "the path contains a NUL character");
  return text;
}

long long int_arg(const py::handle& value, const std::string& where, const std::string& key) {
  // bool is an int in Python, but True steps are a mistake, not a count (NumPy's too).
  const bool numpy_bool = py::hasattr(value, "dtype") && py::hasattr(value.attr("dtype"), "kind") &&
                          py::str(value.attr("dtype").attr("kind")).cast<std::string>() == "b";
  if (py::isinstance<py::bool_>(value) || numpy_bool || !PyIndex_Check(value.ptr()))
    throw py::type_error(where + ": argument '" + key + "' must be an int (got " +
                         type_name(value) + ")");
  const long long v =
      PyLong_AsLongLong(py::reinterpret_steal<py::object>(PyNumber_Index(value.ptr())).ptr());
  if (v == -1 && PyErr_Occurred()) {
    PyErr_Clear();
    fail(where, key, "is too large (got " + py::str(value).cast<std::string>() + ")");
  }
  return v;
}

double real_arg(const py::handle& value, const std::string& where, const std::string& key) {
  if (py::isinstance<py::bool_>(value) || py::isinstance<py::str>(value) ||
      py::isinstance<py::bytes>(value) || !PyNumber_Check(value.ptr()))
    throw py::type_error(where + ": argument '" + key + "' must be a number (got " +
                         type_name(value) + ")");
  const double v = PyFloat_AsDouble(value.ptr());
  if (v == -1.0 && PyErr_Occurred()) {
    PyErr_Clear();
    fail(where, key, "cannot be read as a number (got " + type_name(value) + ")");
  }
  return v;
}

bool bool_arg(const py::handle& value, const std::string& where, const std::string& key) {
  if (!py::isinstance<py::bool_>(value) &&
      !(py::hasattr(value, "dtype") && py::str(value.attr("dtype")).cast<std::string>() == "bool"))
    throw py::type_error(where + ": argument '" + key + "' must be a bool (got " +
                         type_name(value) + ")");
  return PyObject_IsTrue(value.ptr()) == 1;
}

// A key as `--set` takes it: table.key, table[0].key. Anything else (a newline, '=', a quote)
// would reach the scene reader as text and could write other keys than the one named.
std::string key_arg(const py::handle& value, const std::string& where, const std::string& what) {
  const std::string key = str_of(value, where, what);
  bool ok = !key.empty();
  for (const char c : key)
    if (!(std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == '-' || c == '.' ||
          c == '[' || c == ']'))
      ok = false;
  if (!ok)
    fail(where, key,
         "is not a key path (letters, digits, '_', '-', '.', and [index]: table.key, "
         "table[0].key)");
  return key;
}

std::string override_text(const std::string& key, const py::handle& value) {
  return key + "=" + toml_value(value, key);
}

std::vector<std::string> overrides_from(const py::object& overrides) {
  const std::string where = "<maille.Simulation>";
  std::vector<std::string> out;
  if (overrides.is_none()) return out;
  if (py::isinstance<py::dict>(overrides)) {
    for (const auto& [k, v] : overrides.cast<py::dict>())
      out.push_back(override_text(key_arg(k, where, "overrides"), v));
    return out;
  }
  if (py::isinstance<py::str>(overrides) || py::isinstance<py::bytes>(overrides) ||
      !py::isinstance<py::iterable>(overrides))
    throw py::type_error(where +
                         ": argument 'overrides' must be a dict {key: value} or a list of "
                         "\"KEY=VALUE\" strings (got " +
                         type_name(overrides) + ")");
  for (const auto& item : overrides) {
    const std::string text = str_of(item, where, "overrides");
    const auto eq = text.find('=');
    key_arg(py::str(text.substr(0, eq)), where, "overrides");  // the key as a path
    if (text.find_first_of("\n\r") != std::string::npos)
      fail(where, text.substr(0, eq), "a \"KEY=VALUE\" override is one line");
    out.push_back(text);
  }
  return out;
}

std::string override_key(const std::string& text) {
  return text.substr(0, text.find('='));
}

void merge_override(std::vector<std::string>& sets, std::string text) {
  const std::string key = override_key(text);
  std::erase_if(sets, [&](const std::string& s) { return override_key(s) == key; });
  sets.push_back(std::move(text));
}

Scene settings_scene(const std::vector<std::string>& sets) {
  static const LinkKindRegistry kinds = LinkKindRegistry::with_builtins();
  static const StageRegistry stages = StageRegistry::with_builtins();
  return value_or_throw(
      parse_scene("[[mass]]\nposition = [0, 0, 0]\n", "<maille.Model>", kinds, stages, sets));
}

}  // namespace maille::python
