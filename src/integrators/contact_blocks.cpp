#include "contact_blocks.hpp"

#include <algorithm>

namespace maille {

bool ObstacleBlocks::take(std::span<PointContacts* const> obstacles, const State& s, Real h,
                          std::span<const std::uint32_t> free, Vec3* rhs) {
  if (obstacles.empty()) return false;
  const std::size_t n = s.size();
  if (blocks.size() != n) {  // sized once per model
    blocks.assign(n, Mat3{});
    stiffness.assign(n, Mat3{});
    sink.assign(n, Vec3{});
  }
  const Vec3* x = s.x().data();
  const Vec3* v = s.v().data();
  std::fill(blocks.begin(), blocks.end(), Mat3{});
  std::fill(stiffness.begin(), stiffness.end(), Mat3{});
  for (PointContacts* c : obstacles) {
    c->set_time(s.time);
    c->add_terms(free, x, v, Real(1) / h, sink.data(), blocks.data(), nullptr);
    if (rhs) c->add_terms(free, x, v, 0, sink.data(), stiffness.data(), nullptr);
    c->set_time(s.time + h);
  }
  for (const std::uint32_t i : free) {
    blocks[i] *= h * h;
    if (rhs) rhs[i] -= (stiffness[i] * v[i]) * (h * h);
  }
  return true;
}

}  // namespace maille
