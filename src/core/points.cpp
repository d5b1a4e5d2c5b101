#include "maille/points.hpp"

#include <algorithm>
#include <cassert>

namespace maille {

std::uint32_t PointPool::add(PointKind k, Real m, const Vec3& position, const Vec3& velocity) {
  assert(m > 0);
  mass.push_back(m);
  inv_mass.push_back(k == PointKind::free ? Real(1) / m : Real(0));
  kind.push_back(k);
  initial_position.push_back(position);
  initial_velocity.push_back(k == PointKind::free ? velocity : Vec3{});
  return size() - 1;
}

std::uint32_t PointPool::count(PointKind k) const {
  return static_cast<std::uint32_t>(std::count(kind.begin(), kind.end(), k));
}

void PointPool::set_kind(std::uint32_t i, PointKind k) {
  kind[i] = k;
  inv_mass[i] = k == PointKind::free ? Real(1) / mass[i] : Real(0);
  if (k != PointKind::free) initial_velocity[i] = {};
}

}  // namespace maille
