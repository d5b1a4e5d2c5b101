#include "gust.hpp"
#include "maille/fields.hpp"

namespace maille {

// One point at a time (tools and tests); the wind stage evaluates the same field face by face in
// a vectorised loop (gust.hpp, field_forces.cpp).
Vec3 WindField::at(const Vec3& p, double t) const {
  const gust::Basis b = gust::basis(*this, t);
  return b.steady ? b.mean : gust::at(b, p);
}

}  // namespace maille
