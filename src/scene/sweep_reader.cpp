// The sweep file (include/maille/sweep.hpp): read with toml++ behind the same guard as scene
// files, checked key by key with the line of each error, and its axes' values turned back into
// TOML text for the `--set` path of load_scene.
#include <algorithm>
#include <array>
#include <cctype>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstring>
#include <fstream>
#include <sstream>

#include "maille/limits.hpp"
#include "maille/scene.hpp"
#include "maille/sweep.hpp"
#include "sweep_keys.hpp"
#include "toml_guard.hpp"

#define TOML_HEADER_ONLY 0
#include <toml++/toml.h>

namespace maille {

namespace {

struct SweepFailure {
  InputError error;
};

[[noreturn]] void fail(const std::string& file, const toml::source_region& where,
                       const std::string& key, const std::string& message) {
  throw SweepFailure{{file, static_cast<int>(where.begin.line),
                      static_cast<int>(where.begin.column), key, message}};
}

// A double as the shortest text that reads back to it, kept a TOML float ("100.0", not "100").
std::string float_text(double v) {
  char buffer[64];
  const auto r = std::to_chars(buffer, buffer + sizeof buffer, v);
  std::string text(buffer, r.ptr);
  if (text.find_first_of(".eEni") == std::string::npos) text += ".0";
  return text;
}

// A value as TOML text: numbers at their shortest exact form, strings quoted and escaped by
// toml++, arrays and inline tables element by element.
std::string toml_text(const toml::node& n) {
  if (const auto* f = n.as_floating_point()) return float_text(f->get());
  if (const auto* i = n.as_integer()) return std::to_string(i->get());
  if (const auto* b = n.as_boolean()) return b->get() ? "true" : "false";
  if (const auto* a = n.as_array()) {
    std::string s = "[";
    for (std::size_t k = 0; k < a->size(); ++k) s += (k ? ", " : "") + toml_text(*a->get(k));
    return s + "]";
  }
  if (const auto* t = n.as_table()) {
    std::string s = "{";
    bool first = true;
    for (auto&& [key, value] : *t) {
      // A bare key as it is; any other quoted like a string.
      const std::string name(key.str());
      const bool bare = !name.empty() && std::all_of(name.begin(), name.end(), [](char c) {
        return std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == '-';
      });
      const std::string line = bare ? name : toml_text(toml::value<std::string>(name));
      s += (first ? " " : ", ") + line + " = " + toml_text(value);
      first = false;
    }
    return s + (first ? "}" : " }");
  }
  std::ostringstream s;  // strings, dates and times
  n.visit([&](auto&& v) { s << toml::toml_formatter{v, toml::format_flags::none}; });
  return s.str();
}

// Key paths as --set takes them: table.key, table[0].key (checked fully by the probe load).
bool key_path_characters(const std::string& key) {
  return !key.empty() && std::all_of(key.begin(), key.end(), [](char c) {
    return std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == '-' || c == '.' ||
           c == '[' || c == ']';
  });
}

}  // namespace

std::span<const StageKey<Sweep>> sweep_keys() {
  static const std::array<StageKey<Sweep>, 4> keys{
      custom<Sweep>("scene", KeyType::text,
                    {.doc = "the scene file, relative to the sweep file",
                     .default_doc = "required",
                     .range_doc = "a scene file"}),
      // Read by the reader (custom), within the range declared here and checked there.
      StageKey<Sweep>{"duration",
                      KeyType::number,
                      {.unit = "s",
                       .doc = "simulated time of each case, as `maille run --duration`",
                       .default_doc = "the scene's `[simulation] duration`"},
                      Bound::positive,
                      0,
                      limits::max_duration},
      custom<Sweep>("axes", KeyType::table,
                    {.doc = "each key a scene key path exactly as `maille run --set KEY=VALUE` "
                            "takes it (`simulation.step`, `flag[0].stiffness`, "
                            "`fields.wind.velocity`, `self_collision.broad_phase`); each value a "
                            "non-empty array of the values to try, any TOML value "
                            "(`[[7.0, 0.0, 1.5], [10.0, 0.0, 1.5]]` for a vector, "
                            "`[\"brute\", \"uniform\"]` for a choice)",
                     .default_doc = "required",
                     .range_doc = "at least one axis"}),
      custom<Sweep>("output", KeyType::table,
                    {.doc = "`frames = true`: write each case's frames (the scene's "
                            "`output_every`, PLY) under DIR/cases/<id>/",
                     .default_doc = "`frames = false`",
                     .range_doc = "the key `frames` (true or false)"}),
  };
  return keys;
}

std::string sweep_key_list() {
  std::string s;
  for (const auto& k : sweep_keys()) {
    const std::string key(k.key);
    s += (s.empty() ? "" : ", ") + (k.type == KeyType::table ? "[" + key + "]" : key);
  }
  return s;
}

namespace {

Sweep read(const toml::table& root, const std::filesystem::path& path) {
  const std::string file = path.string();
  Sweep s;
  s.source = path;
  bool have_scene = false, have_axes = false;
  for (auto&& [k, v] : root) {
    const std::string key(k.str());
    if (key == "scene") {
      const auto* text = v.as_string();
      if (!text || text->get().empty())
        fail(file, v.source(), key, "must be the path of a scene file (relative to this file)");
      if (text->get().find('\0') != std::string::npos)
        fail(file, v.source(), key, "the path contains a NUL character");
      const std::filesystem::path scene(text->get());
      s.scene = scene.is_absolute() ? scene : (path.parent_path() / scene).lexically_normal();
      s.scene_line = static_cast<int>(k.source().begin.line);
      have_scene = true;
    } else if (key == "duration") {
      const auto d = v.value<double>();
      if (!d || !std::isfinite(*d) || !(*d > 0) || *d > limits::max_duration) {
        std::ostringstream m;
        m << "must be a number of seconds in (0, " << limits::max_duration << "]";
        fail(file, v.source(), key, m.str());
      }
      s.duration = *d;
    } else if (key == "axes") {
      const auto* axes = v.as_table();
      if (!axes) fail(file, v.source(), key, "must be a table: [axes] then KEY = [values]");
      for (auto&& [ak, av] : *axes) {
        const std::string akey(ak.str());
        const std::string where = "axes.\"" + akey + "\"";
        if (!key_path_characters(akey))
          fail(file, ak.source(), where,
               "an axis is named by a scene key path as for --set (table.key, table[0].key)");
        const auto* values = av.as_array();
        if (!values || values->empty())
          fail(file, av.source(), where, "must be a non-empty array of values: [v1, v2, ...]");
        SweepAxis axis;
        axis.key = akey;
        axis.line = static_cast<int>(ak.source().begin.line);
        axis.column = static_cast<int>(ak.source().begin.column);
        for (const auto& value : *values) {
          axis.values.push_back(toml_text(value));
          axis.labels.push_back(value.is_string() ? value.as_string()->get() : axis.values.back());
        }
        s.axes.push_back(std::move(axis));
      }
      if (s.axes.empty()) fail(file, v.source(), key, "has no axis: give KEY = [values]");
      have_axes = true;
    } else if (key == "output") {
      const auto* output = v.as_table();
      if (!output) fail(file, v.source(), key, "must be a table: [output] then frames = true");
      for (auto&& [ok, ov] : *output) {
        if (ok.str() != "frames")
          fail(file, ok.source(), "output." + std::string(ok.str()),
               "unknown key (the [output] table has: frames)");
        const auto* b = ov.as_boolean();
        if (!b) fail(file, ov.source(), "output.frames", "must be true or false");
        s.frames = b->get();
      }
    } else {
      fail(file, k.source(), key, "unknown key (a sweep file has: " + sweep_key_list() + ")");
    }
  }
  if (!have_scene) fail(file, root.source(), "scene", "is required but missing");
  if (!have_axes)
    fail(file, root.source(), "axes", "is required but missing: [axes] KEY = [values]");
  // toml++ keeps a table's keys sorted: the file's order is their position.
  std::stable_sort(s.axes.begin(), s.axes.end(), [](const SweepAxis& a, const SweepAxis& b) {
    return std::pair(a.line, a.column) < std::pair(b.line, b.column);
  });
  std::uint64_t cases = 1;
  for (const auto& a : s.axes) {
    cases *= a.values.size();
    if (cases > max_sweep_cases)
      throw SweepFailure{{file, a.line, a.column, "axes",
                          "the axes make more than " + std::to_string(max_sweep_cases) + " cases"}};
  }
  return s;
}

}  // namespace

std::uint64_t Sweep::case_count() const {
  std::uint64_t n = axes.empty() ? 0 : 1;
  for (const auto& a : axes) n *= a.values.size();
  return n;
}

std::vector<std::size_t> Sweep::coordinates(std::uint64_t i) const {
  std::vector<std::size_t> c(axes.size());
  for (std::size_t k = axes.size(); k-- > 0;) {
    c[k] = static_cast<std::size_t>(i % axes[k].values.size());
    i /= axes[k].values.size();
  }
  return c;
}

std::vector<std::string> Sweep::overrides(std::uint64_t i) const {
  const auto c = coordinates(i);
  std::vector<std::string> sets;
  for (std::size_t k = 0; k < axes.size(); ++k)
    sets.push_back(axes[k].key + "=" + axes[k].values[c[k]]);
  return sets;
}

std::string Sweep::case_id(std::uint64_t i) const {
  const std::size_t width = std::max<std::size_t>(4, std::to_string(case_count() - 1).size());
  std::string id = std::to_string(i);
  return std::string(width - std::min(width, id.size()), '0') + id;
}

Result<Sweep> load_sweep(const std::filesystem::path& path) {
  const std::string file = path.string();
  std::error_code ec;
  const auto status = std::filesystem::status(path, ec);
  if (ec || !std::filesystem::exists(status))
    return InputError{file, 0, 0, "", "cannot open the sweep file: no such file or directory"};
  if (!std::filesystem::is_regular_file(status))
    return InputError{file, 0, 0, "", "is not a regular file"};
  if (std::filesystem::file_size(path, ec) > limits::max_scene_file_bytes)
    return InputError{file, 0, 0, "", "is larger than 64 MiB: not a sweep file"};
  std::ifstream in(path, std::ios::binary);
  if (!in)
    return InputError{file, 0, 0, "",
                      std::string("cannot open the sweep file: ") + std::strerror(errno)};
  std::stringstream text;
  text << in.rdbuf();
  const std::string body = text.str();
  if (const auto hazard = find_toml_hazard(body))  // a toml++ 3.3 bug (toml_guard.hpp)
    return InputError{file, hazard->line, hazard->column, "", hazard->message};
  try {
    const toml::table root = toml::parse(std::string_view(body), std::string_view(file));
    return read(root, path);
  } catch (const toml::parse_error& e) {
    return InputError{
        file, static_cast<int>(e.source().begin.line), static_cast<int>(e.source().begin.column),
        "", toml_syntax_message(body, static_cast<int>(e.source().begin.line), e.description())};
  } catch (const SweepFailure& f) {
    return f.error;
  }
}

std::optional<InputError> check_sweep_keys(const Sweep& sweep) {
  const std::string file = sweep.source.string();
  if (Result<Scene> plain = load_scene(sweep.scene); !plain)
    return InputError{file, sweep.scene_line, 1, "scene",
                      "the scene does not load: " + plain.error().to_string()};
  for (const auto& axis : sweep.axes) {
    const std::vector<std::string> set{axis.key + "=" + axis.values.front()};
    Result<Scene> probe = load_scene(sweep.scene, set);
    if (probe) continue;
    const InputError& e = probe.error();
    // The override's path itself is wrong (malformed, an index beyond the scene's tables, a value
    // where a table is expected): apply_overrides reports it from "--set". Or the scene reader
    // does not know the key (or a table on its path).
    const bool path_error = e.file == "--set";
    const bool unknown = e.message.rfind("unknown key", 0) == 0 &&
                         (axis.key == e.key || axis.key.rfind(e.key + ".", 0) == 0 ||
                          axis.key.rfind(e.key + "[", 0) == 0);
    if (path_error || unknown) {
      std::string why = e.message;
      if (const auto at = why.find(" (in --set "); at != std::string::npos) why.resize(at);
      return InputError{file, axis.line, axis.column, "axes.\"" + axis.key + "\"",
                        "not a key of the scene " + sweep.scene.string() + ": " +
                            (e.key.empty() || e.key == axis.key ? "" : "'" + e.key + "': ") + why};
    }
  }
  return std::nullopt;
}

std::optional<InputError> check_sweep_values(const Sweep& sweep) {
  const std::string file = sweep.source.string();
  for (const auto& axis : sweep.axes)
    for (std::size_t k = 0; k < axis.values.size(); ++k) {
      const std::vector<std::string> set{axis.key + "=" + axis.values[k]};
      Result<Scene> probe = load_scene(sweep.scene, set);
      if (probe) continue;
      std::string why = probe.error().message;
      if (const auto at = why.find(" (in --set "); at != std::string::npos) why.resize(at);
      return InputError{file, axis.line, axis.column, "axes.\"" + axis.key + "\"",
                        "value " + axis.labels[k] + " (value " + std::to_string(k + 1) + " of " +
                            std::to_string(axis.values.size()) + ") is refused by the scene " +
                            sweep.scene.string() + ": " + why};
    }
  return std::nullopt;
}

bool is_sweep_file(const std::filesystem::path& path) {
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec) ||
      std::filesystem::file_size(path, ec) > limits::max_scene_file_bytes)
    return false;
  std::ifstream in(path, std::ios::binary);
  std::stringstream text;
  text << in.rdbuf();
  const std::string body = text.str();
  if (find_toml_hazard(body)) return false;
  try {
    const toml::table root = toml::parse(std::string_view(body), std::string_view(path.string()));
    return root.contains("axes") || (root.contains("scene") && root["scene"].is_string());
  } catch (const toml::parse_error&) {
    return false;
  }
}

}  // namespace maille
