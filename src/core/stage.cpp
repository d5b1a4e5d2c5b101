#include "maille/stage.hpp"

namespace maille {

std::string_view to_string(Phase p) {
  switch (p) {
    case Phase::forces:
      return "forces";
    case Phase::response:
      return "response";
    case Phase::after_integration:
      return "after_integration";
  }
  return "?";
}

}  // namespace maille
