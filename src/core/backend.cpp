#include "maille/backend.hpp"

#include <algorithm>

namespace maille {

BackendRegistry& BackendRegistry::global() {
  static BackendRegistry registry = [] {
    BackendRegistry r;
    r.add(
        {"cpu", "the reference: every stage, every scheme, double precision, OpenMP threads", {}});
    return r;
  }();
  return registry;
}

void BackendRegistry::add(Entry e) {
  auto same = [&](const Entry& x) { return x.name == e.name; };
  if (auto it = std::find_if(entries_.begin(), entries_.end(), same); it != entries_.end())
    *it = std::move(e);
  else
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
