// The CG systems' registry, and the 3x3 inverse every implicit solver uses.
#include "implicit_system.hpp"

#include <cmath>

namespace maille {

void register_implicit_systems(ImplicitSystems& systems);  // generated: systems/*.cpp

const ImplicitSystems& ImplicitSystems::builtin() {
  static const ImplicitSystems systems = [] {
    ImplicitSystems r;
    register_implicit_systems(r);
    return r;
  }();
  return systems;
}

std::unique_ptr<ImplicitSystem> make_implicit_system(ImplicitSolver solver, const Model& m,
                                                     int threads) {
  const ImplicitSystemEntry* e = ImplicitSystems::builtin().find(to_string(solver));
  return e ? e->make(m, threads) : nullptr;
}

Mat3 inverse_spd(const Mat3& a) {
  const auto& m = a.m;
  const Real c00 = m[1][1] * m[2][2] - m[1][2] * m[2][1];
  const Real c01 = m[1][2] * m[2][0] - m[1][0] * m[2][2];
  const Real c02 = m[1][0] * m[2][1] - m[1][1] * m[2][0];
  const Real det = m[0][0] * c00 + m[0][1] * c01 + m[0][2] * c02;
  if (!(std::abs(det) > 0)) return Mat3::identity();
  Mat3 r;
  r.m[0][0] = c00;
  r.m[0][1] = m[0][2] * m[2][1] - m[0][1] * m[2][2];
  r.m[0][2] = m[0][1] * m[1][2] - m[0][2] * m[1][1];
  r.m[1][0] = c01;
  r.m[1][1] = m[0][0] * m[2][2] - m[0][2] * m[2][0];
  r.m[1][2] = m[0][2] * m[1][0] - m[0][0] * m[1][2];
  r.m[2][0] = c02;
  r.m[2][1] = m[0][1] * m[2][0] - m[0][0] * m[2][1];
  r.m[2][2] = m[0][0] * m[1][1] - m[0][1] * m[1][0];
  return r * (Real(1) / det);
}

}  // namespace maille
