// Scene keyword -> link kind. The scene reader and `maille info` look kinds up here; a program
// (or a test) registers its own kinds beside the built-ins without touching the engine.
#pragma once

#include <functional>
#include <memory>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "maille/link_pool.hpp"
#include "maille/names.hpp"

namespace maille {

class LinkKindRegistry {
 public:
  struct Entry {
    std::string keyword;
    std::vector<ParamInfo> fields;
    std::function<std::unique_ptr<LinkPoolBase>()> make_pool;
  };

  // Throws std::logic_error for a keyword already registered (names.hpp: registered_twice).
  template <LinkKind K>
  void add() {
    if (find(K::keyword)) registered_twice("link kind registry", K::keyword);
    entries_.push_back({std::string(K::keyword), LinkPool<K>{}.fields(),
                        [] { return std::make_unique<LinkPool<K>>(); }});
  }
  const Entry* find(std::string_view keyword) const;
  std::span<const Entry> entries() const { return entries_; }
  std::string keywords() const;  // "spring, damper, ..." for messages

  // A registry holding the built-in kinds (the list: src/links/builtin_kinds.cpp).
  static LinkKindRegistry with_builtins();

 private:
  std::vector<Entry> entries_;
};

}  // namespace maille
