#include "maille/link_registry.hpp"

namespace maille {

const LinkKindRegistry::Entry* LinkKindRegistry::find(std::string_view keyword) const {
  for (const auto& e : entries_)
    if (e.keyword == keyword) return &e;
  return nullptr;
}

std::string LinkKindRegistry::keywords() const {
  std::string s;
  for (const auto& e : entries_) s += (s.empty() ? "" : ", ") + e.keyword;
  return s;
}

}  // namespace maille
