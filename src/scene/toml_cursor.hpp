// TomlCursor: reads one TOML table key by key, checking types and ranges, remembering which keys
// were read so that finish() can name any unknown key. Every error carries file, line, column
// and the dotted key path, and is thrown as SceneFailure (caught by the scene reader).
#pragma once

#include <initializer_list>
#include <optional>
#include <set>
#include <string>
#include <string_view>
#include <vector>

#define TOML_HEADER_ONLY 0
#include <toml++/toml.h>

#include "maille/limits.hpp"
#include "maille/link_kind.hpp"
#include "maille/result.hpp"
#include "maille/scene_table.hpp"

namespace maille {

struct SceneFailure {
  InputError error;
};

class TomlCursor final : public SceneTable {
 public:
  TomlCursor(const toml::table& table, std::string file, std::string path);
  TomlCursor(const TomlCursor&) = default;
  TomlCursor(TomlCursor&&) = default;

  const std::string& path() const override { return path_; }
  const std::string& file() const override { return file_; }
  bool has(std::string_view key) const override { return table_.contains(key); }
  bool has_text(std::string_view key) const override {
    const toml::node* n = table_.get(key);
    return n && n->is_string();
  }
  bool has_integer(std::string_view key) const override {
    const toml::node* n = table_.get(key);
    return n && n->is_integer();
  }

  Real real(std::string_view key, Bound bound) override;  // required
  Real real(std::string_view key, Real fallback, Bound bound) override;
  std::optional<Real> maybe_real(std::string_view key, Bound bound);
  std::int64_t integer(std::string_view key, std::int64_t fallback, std::int64_t min,
                       std::int64_t max) override;
  bool boolean(std::string_view key, bool fallback) override;
  std::string text(std::string_view key);  // required
  using SceneTable::text;
  std::string text(std::string_view key, std::string fallback,
                   std::span<const std::string_view> choices) override;
  Vec3 vec3(std::string_view key);  // required
  Vec3 vec3(std::string_view key, Vec3 fallback) override;
  std::vector<std::string> texts(std::string_view key, std::vector<std::string> fallback) override;
  std::optional<std::vector<double>> numbers(std::string_view key) override;
  std::vector<std::int64_t> integers(std::string_view key, std::vector<std::int64_t> fallback,
                                     std::int64_t min, std::int64_t max) override;
  // Fails at `key` unless lo <= value <= hi: "must be in [lo, hi] UNIT (got value)".
  void check_range(std::string_view key, Real value, Real lo, Real hi,
                   std::string_view unit) const override;
  // The raw node (marked as read); null when absent.
  const toml::node* node(std::string_view key);
  std::optional<TomlCursor> table(std::string_view key);
  std::unique_ptr<SceneTable> child(std::string_view key) override;
  std::vector<TomlCursor> tables(std::string_view key);  // an array of tables

  [[noreturn]] void fail(std::string_view key, const std::string& message) const override;
  [[noreturn]] void fail_item(std::string_view key, std::size_t index,
                              const std::string& message) const override;
  [[noreturn]] void fail_at(const toml::source_region& where, std::string_view key,
                            const std::string& message) const;
  void finish() const override;  // fails on the first key never read

 private:
  std::string key_path(std::string_view key) const;
  const toml::node& require(std::string_view key);

  const toml::table& table_;
  std::string file_;
  std::string path_;
  std::set<std::string, std::less<>> used_;
};

// "must be > 0 (got -1)" style check of a bound; returns the message or empty.
std::string check_bound(Real value, Bound bound);

}  // namespace maille
