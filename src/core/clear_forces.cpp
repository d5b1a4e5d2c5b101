#include <algorithm>

#include "stages.hpp"

namespace maille::stages {

void clear_forces(State& s) {
  auto f = s.f();
  std::fill(f.begin(), f.end(), Vec3{});
}

}  // namespace maille::stages
