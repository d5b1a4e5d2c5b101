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

}  // namespace maille
