#include "maille/stage_registry.hpp"

namespace maille {

const StageRegistry::Entry* StageRegistry::find(std::string_view table) const {
  for (const auto& e : entries_)
    if (e.table == table) return &e;
  return nullptr;
}

// Built-in stage tables register here, one line each (self-collision and obstacles when the
// collision themes land).
StageRegistry StageRegistry::with_builtins() {
  StageRegistry r;
  return r;
}

}  // namespace maille
