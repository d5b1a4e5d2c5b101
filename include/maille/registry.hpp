// What every registry of the engine is (link kinds, integrators, backends, scene tables that
// make stages): entries found by name, in registration order, each name once.
#pragma once

#include <span>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "maille/names.hpp"

namespace maille {

// `Key` is the member of Entry that names it (`&Entry::name`, `&Entry::keyword`, ...); `what`
// names the registry in the error a second registration of a name throws (registered_twice).
template <class Entry, auto Key>
class Registry {
 public:
  explicit Registry(std::string_view what) : what_(what) {}

  // Throws std::logic_error for a name already registered.
  void add(Entry e) {
    if (find(e.*Key)) registered_twice(what_, e.*Key);
    entries_.push_back(std::move(e));
  }
  const Entry* find(std::string_view name) const {
    for (const auto& e : entries_)
      if (e.*Key == name) return &e;
    return nullptr;
  }
  std::span<const Entry> entries() const { return entries_; }
  // "a, b, c": the names in registration order, for messages.
  std::string names() const {
    std::string s;
    for (const auto& e : entries_) s += (s.empty() ? "" : ", ") + std::string(e.*Key);
    return s;
  }

 private:
  std::string_view what_;
  std::vector<Entry> entries_;
};

}  // namespace maille
