// The force laws shared with the GPU backend, compiled as C++ in namespace maille::law:
// include/maille/detail/link_laws.glsl (`vec3` is Vec3, `mat3` Mat3 and `real` is Real here) and
// include/maille/detail/wind_law.glsl (float). A link kind that has such a law names it in
// `shared_law` (link_kind.hpp); the GPU backend then runs the kind too. Also
// include/maille/detail/obstacle_laws.glsl: the canonical shapes' distances and the geometric
// contact law (shapes.cpp, the geometric obstacle stage and the GPU's obstacle kernels); and
// include/maille/detail/contact_laws.glsl: self-collision's point-triangle and edge-edge
// contacts (closest points, penalty, force and block).
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>

#include "maille/mat3.hpp"
#include "maille/vec3.hpp"

namespace maille::law {

using vec3 = Vec3;
using mat3 = Mat3;
using real = Real;
using uint = std::uint32_t;
using std::abs;
using std::clamp;
using std::max;
using std::min;
using std::sqrt;

inline Vec3 zero3() {
  return {};
}
inline Mat3 outer3(const Vec3& a, const Vec3& b) {
  return Mat3::outer(a, b);
}
inline Mat3 identity3() {
  return Mat3::identity();
}
inline Real largest_real() {
  return std::numeric_limits<Real>::max();
}

#define MAILLE_SHARED inline
#define MAILLE_UNUSED(x) static_cast<void>(x)
#define MAILLE_OUT(T) T&
#define MAILLE_INOUT(T) T&
#include "maille/detail/contact_laws.glsl"
#include "maille/detail/link_laws.glsl"
#include "maille/detail/obstacle_laws.glsl"
#include "maille/detail/wind_law.glsl"
#undef MAILLE_INOUT
#undef MAILLE_OUT
#undef MAILLE_UNUSED
#undef MAILLE_SHARED

}  // namespace maille::law
