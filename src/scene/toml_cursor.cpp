#define TOML_IMPLEMENTATION
#include "toml_cursor.hpp"

#include <cmath>
#include <limits>
#include <sstream>

namespace maille {

std::string InputError::to_string() const {
  std::ostringstream s;
  s << file;
  if (line > 0) s << ":" << line << ":" << column;
  s << ": error: ";
  if (!key.empty()) s << "key '" << key << "': ";
  s << message;
  return s.str();
}

std::string check_bound(Real value, Bound bound) {
  std::ostringstream s;
  if (!std::isfinite(value))
    s << "must be a finite number";
  else if (bound == Bound::positive && !(value > 0))
    s << "must be > 0 (got " << value << ")";
  else if (bound == Bound::non_negative && !(value >= 0))
    s << "must be >= 0 (got " << value << ")";
  return s.str();
}

TomlCursor::TomlCursor(const toml::table& table, std::string file, std::string path)
    : table_(table), file_(std::move(file)), path_(std::move(path)) {}

std::string TomlCursor::key_path(std::string_view key) const {
  if (key.empty()) return path_;
  return path_.empty() ? std::string(key) : path_ + "." + std::string(key);
}

// A value given on the command line (`--set`, src/scene/overrides.cpp) has no place in the file:
// its source is "--set", or none at all; the error says so.
void TomlCursor::fail_at(const toml::source_region& where, std::string_view key,
                         const std::string& message) const {
  const bool from_set = (where.path && *where.path == "--set") || where.begin.line == 0;
  if (from_set && table_.get(key))
    throw SceneFailure{{file_ + " (--set)", 0, 0, key_path(key), message}};
  throw SceneFailure{{file_, static_cast<int>(where.begin.line),
                      static_cast<int>(where.begin.column), key_path(key), message}};
}

void TomlCursor::fail(std::string_view key, const std::string& message) const {
  const toml::node* n = table_.get(key);
  fail_at(n ? n->source() : table_.source(), key, message);
}

void TomlCursor::fail_item(std::string_view key, std::size_t index,
                           const std::string& message) const {
  const toml::node* n = table_.get(key);
  const toml::array* a = n ? n->as_array() : nullptr;
  if (!a || index >= a->size()) fail(key, message);
  fail_at((*a)[index].source(), key, message);
}

const toml::node& TomlCursor::require(std::string_view key) {
  const toml::node* n = node(key);
  if (!n) fail_at(table_.source(), key, "is required but missing");
  return *n;
}

const toml::node* TomlCursor::node(std::string_view key) {
  used_.insert(std::string(key));
  return table_.get(key);
}

Real TomlCursor::real(std::string_view key, Bound bound) {
  const toml::node& n = require(key);
  const std::optional<double> v = n.value<double>();
  if (!n.is_number() || !v) fail(key, "must be a number");
  const Real r = static_cast<Real>(*v);
  if (const std::string why = check_bound(r, bound); !why.empty()) fail(key, why);
  return r;
}

Real TomlCursor::real(std::string_view key, Real fallback, Bound bound) {
  return has(key) ? real(key, bound) : (used_.insert(std::string(key)), fallback);
}

std::optional<Real> TomlCursor::maybe_real(std::string_view key, Bound bound) {
  if (!has(key)) return std::nullopt;
  return real(key, bound);
}

std::int64_t TomlCursor::integer(std::string_view key, std::int64_t fallback, std::int64_t min,
                                 std::int64_t max) {
  const toml::node* n = node(key);
  if (!n) return fallback;
  if (!n->is_integer()) fail(key, "must be an integer");
  const std::int64_t v = *n->value<std::int64_t>();
  if (v < min || v > max) {
    std::ostringstream s;
    s << "must be in [" << min << ", " << max << "] (got " << v << ")";
    fail(key, s.str());
  }
  return v;
}

bool TomlCursor::boolean(std::string_view key, bool fallback) {
  const toml::node* n = node(key);
  if (!n) return fallback;
  if (!n->is_boolean()) fail(key, "must be true or false");
  return *n->value<bool>();
}

std::string TomlCursor::text(std::string_view key) {
  const toml::node& n = require(key);
  if (!n.is_string()) fail(key, "must be a string");
  return *n.value<std::string>();
}

std::string TomlCursor::text(std::string_view key, std::string fallback,
                             std::span<const std::string_view> choices) {
  const std::string v = has(key) ? text(key) : (used_.insert(std::string(key)), fallback);
  if (choices.empty()) return v;
  for (auto c : choices)
    if (c == v) return v;
  std::string list;
  for (auto c : choices) list += (list.empty() ? "" : ", ") + std::string(c);
  fail(key, "must be one of " + list + " (got '" + v + "')");
}

Vec3 TomlCursor::vec3(std::string_view key) {
  const toml::node& n = require(key);
  const toml::array* a = n.as_array();
  if (!a || a->size() != 3) fail(key, "must be an array of 3 numbers [x, y, z]");
  Real out[3];
  for (std::size_t i = 0; i < 3; ++i) {
    const auto v = (*a)[i].value<double>();
    if (!(*a)[i].is_number() || !v || !std::isfinite(*v))
      fail_at((*a)[i].source(), key, "must be an array of 3 finite numbers [x, y, z]");
    if (std::abs(*v) > limits::max_coordinate) {  // positions, velocities, directions alike
      std::ostringstream s;
      s << "each component must be within +-" << limits::max_coordinate << " (got " << *v << ")";
      fail_at((*a)[i].source(), key, s.str());
    }
    out[i] = static_cast<Real>(*v);
  }
  return {out[0], out[1], out[2]};
}

Vec3 TomlCursor::vec3(std::string_view key, Vec3 fallback) {
  return has(key) ? vec3(key) : (used_.insert(std::string(key)), fallback);
}

std::vector<std::int64_t> TomlCursor::integers(std::string_view key,
                                               std::vector<std::int64_t> fallback, std::int64_t min,
                                               std::int64_t max) {
  const toml::node* n = node(key);
  if (!n) return fallback;
  const toml::array* a = n->as_array();
  std::ostringstream want;
  want << "must be an array of " << fallback.size() << " integers in [" << min << ", " << max
       << "]";
  if (!a || a->size() != fallback.size()) fail(key, want.str());
  std::vector<std::int64_t> out;
  for (const auto& e : *a) {
    if (!e.is_integer()) fail_at(e.source(), key, want.str());
    const std::int64_t v = *e.value<std::int64_t>();
    if (v < min || v > max)
      fail_at(e.source(), key, want.str() + " (got " + std::to_string(v) + ")");
    out.push_back(v);
  }
  return out;
}

void TomlCursor::check_range(std::string_view key, Real value, Real lo, Real hi,
                             std::string_view unit) const {
  if (value >= lo && value <= hi) return;
  std::ostringstream s;
  if (hi == std::numeric_limits<Real>::max())
    s << "must be >= " << lo;
  else
    s << "must be in [" << lo << ", " << hi << "]";
  s << (unit.empty() ? "" : " ") << unit << " (got " << value << ")";
  fail(key, s.str());
}

std::optional<TomlCursor> TomlCursor::table(std::string_view key) {
  const toml::node* n = node(key);
  if (!n) return std::nullopt;
  if (!n->is_table()) fail(key, "must be a table");
  return TomlCursor(*n->as_table(), file_, key_path(key));
}

std::unique_ptr<SceneTable> TomlCursor::child(std::string_view key) {
  auto t = table(key);
  return t ? std::make_unique<TomlCursor>(std::move(*t)) : nullptr;
}

std::vector<TomlCursor> TomlCursor::tables(std::string_view key) {
  std::vector<TomlCursor> out;
  const toml::node* n = node(key);
  if (!n) return out;
  const toml::array* a = n->as_array();
  if (!a) fail(key, "must be an array of tables ([[" + std::string(key) + "]])");
  for (std::size_t i = 0; i < a->size(); ++i) {
    const toml::table* t = (*a)[i].as_table();
    if (!t) fail_at((*a)[i].source(), key, "must be an array of tables");
    out.emplace_back(*t, file_, key_path(key) + "[" + std::to_string(i) + "]");
  }
  return out;
}

void TomlCursor::finish() const {
  for (auto&& [k, v] : table_)
    if (!used_.contains(k.str())) fail_at(k.source(), k.str(), "unknown key");
}

std::optional<std::vector<double>> TomlCursor::numbers(std::string_view key) {
  const toml::node* n = node(key);
  const toml::array* a = n ? n->as_array() : nullptr;
  if (!a) return std::nullopt;
  std::vector<double> out;
  for (const auto& e : *a) {
    if (!e.is_number()) return std::nullopt;
    out.push_back(*e.value<double>());
  }
  return out;
}

std::vector<std::string> TomlCursor::texts(std::string_view key,
                                           std::vector<std::string> fallback) {
  const toml::node* n = node(key);
  if (!n) return fallback;
  const toml::array* a = n->as_array();
  if (!a) fail(key, "must be an array of strings");
  std::vector<std::string> out;
  for (const auto& e : *a) {
    if (!e.is_string()) fail_at(e.source(), key, "must be an array of strings");
    out.push_back(*e.value<std::string>());
  }
  return out;
}

}  // namespace maille
