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
#include "maille/registry.hpp"

namespace maille {

struct LinkKindEntry {
  std::string keyword;
  std::vector<ParamInfo> fields;
  std::function<std::unique_ptr<LinkPoolBase>()> make_pool;
};

class LinkKindRegistry : public Registry<LinkKindEntry, &LinkKindEntry::keyword> {
 public:
  using Entry = LinkKindEntry;
  LinkKindRegistry() : Registry("link kind registry") {}

  // Throws std::logic_error for a keyword already registered (names.hpp: registered_twice).
  template <LinkKind K>
  void add() {
    Registry::add({std::string(K::keyword), LinkPool<K>{}.fields(),
                   [] { return std::make_unique<LinkPool<K>>(); }});
  }

  // A registry holding the built-in kinds (the list: src/links/builtin_kinds.cpp).
  static LinkKindRegistry with_builtins();
};

}  // namespace maille
