// One table of a scene file, as stage factories and custom builders read it: typed getters that
// check ranges, remember which keys were read (the reader then names any unknown key) and fail
// with the file, line, column and dotted key path. The scene reader's TomlCursor implements it.
#pragma once

#include <cstdint>
#include <initializer_list>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "maille/link_kind.hpp"
#include "maille/names.hpp"

namespace maille {

class SceneTable {
 public:
  virtual ~SceneTable() = default;
  virtual const std::string& path() const = 0;  // dotted path of the table, e.g. "obstacle[1]"
  virtual const std::string& file() const = 0;  // the scene file
  virtual bool has(std::string_view key) const = 0;
  virtual bool has_text(std::string_view key) const = 0;     // present and a string
  virtual bool has_integer(std::string_view key) const = 0;  // present and an integer

  virtual Real real(std::string_view key, Bound bound) = 0;  // required
  virtual Real real(std::string_view key, Real fallback, Bound bound) = 0;
  virtual std::int64_t integer(std::string_view key, std::int64_t fallback, std::int64_t min,
                               std::int64_t max) = 0;
  virtual bool boolean(std::string_view key, bool fallback) = 0;
  // A string; with choices, one of them ("must be one of a, b, c (got 'd')").
  virtual std::string text(std::string_view key, std::string fallback,
                           std::span<const std::string_view> choices) = 0;
  std::string text(std::string_view key, std::string fallback,
                   std::initializer_list<std::string_view> choices = {}) {
    return text(key, std::move(fallback), std::span(choices.begin(), choices.size()));
  }
  // A named choice (names.hpp): its table gives the names, the message and the value.
  template <Named E>
  E choice(std::string_view key, E fallback) {
    static constexpr auto names = name_views<E>();
    return *parse_name<E>(text(key, std::string(to_string(fallback)), names));
  }
  virtual Vec3 vec3(std::string_view key, Vec3 fallback) = 0;
  virtual std::vector<std::string> texts(std::string_view key,
                                         std::vector<std::string> fallback) = 0;
  // An array of as many integers as `fallback` has, each in [min, max] (resolutions).
  virtual std::vector<std::int64_t> integers(std::string_view key,
                                             std::vector<std::int64_t> fallback, std::int64_t min,
                                             std::int64_t max) = 0;
  // An array of numbers (integers read as numbers); nullopt when the key is absent or is not
  // such an array: the caller says what it wants ("two numbers, range = [low, high]").
  virtual std::optional<std::vector<double>> numbers(std::string_view key) = 0;

  // A sub-table (inline `key = { ... }` or `[table.key]`), null when absent; it fails on a key
  // of another type. Call finish() on it once read.
  virtual std::unique_ptr<SceneTable> child(std::string_view key) = 0;
  // Fails on the first key never read (a misspelt key is an error, never ignored).
  virtual void finish() const = 0;

  // Fails at `key` unless lo <= value <= hi: "must be in [lo, hi] UNIT (got value)".
  virtual void check_range(std::string_view key, Real value, Real lo, Real hi,
                           std::string_view unit) const = 0;
  // Throws the scene error for `key` (at the key's line when present, else the table's).
  [[noreturn]] virtual void fail(std::string_view key, const std::string& message) const = 0;
  // The same for item `index` of the array at `key` (at the item's line and column when there
  // is such an item, else as fail()): "between = [\"a\", \"nope\"]" blamed on "nope".
  [[noreturn]] virtual void fail_item(std::string_view key, std::size_t index,
                                      const std::string& message) const = 0;
};

}  // namespace maille
