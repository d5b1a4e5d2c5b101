#include "maille/backend.hpp"

#include <algorithm>

namespace maille {

BackendRegistry& BackendRegistry::global() {
  static BackendRegistry registry = [] {
    BackendRegistry r;
    r.add({"cpu", std::string(doc_of(BackendKind::cpu)), {}});
    return r;
  }();
  return registry;
}

void BackendRegistry::add(Entry e) {
  if (find(e.name)) registered_twice("backend registry", e.name);
  entries_.push_back(std::move(e));
}

const BackendRegistry::Entry* BackendRegistry::find(std::string_view name) const {
  for (const auto& e : entries_)
    if (e.name == name) return &e;
  return nullptr;
}

std::string BackendRegistry::names() const {
  std::string out;
  for (const auto& e : entries_) out += (out.empty() ? "" : ", ") + e.name;
  return out;
}

}  // namespace maille
