#include "step_residual.hpp"

#include <algorithm>
#include <cmath>

#include "maille/link_loops.hpp"
#include "maille/stage.hpp"

namespace maille {

void StepResidual::implicit_forces(const Model& m, const State& s, Real h,
                                   const ContactSet* contacts, std::vector<Vec3>& f) {
  const std::size_t n = s.size();
  const Vec3* x = s.x().data();
  const Vec3* v = s.v().data();
  f.assign(n, Vec3{});
  if (blocks_.size() != n) blocks_.assign(n, Mat3{});
  LinkCounters counters;
  for (const auto& pool : m.links.pools()) accumulate_forces(*pool, x, v, f.data(), counters);
  if (contacts) contacts->add_forces(free_, x, v, Real(1) / h, f.data(), blocks_.data());
}

void StepResidual::begin(const Model& m, const State& s, Real h,
                         std::span<const std::uint32_t> free) {
  const std::size_t n = s.size();
  free_ = free;
  vn_.assign(s.v().begin(), s.v().end());
  implicit_forces(m, s, h, nullptr, work_);
  explicit_.resize(n);
  const auto f = s.f();
  for (std::size_t i = 0; i < n; ++i) explicit_[i] = f[i] - work_[i];
}

double StepResidual::end(const Model& m, const State& s, Real h, const ContactSet& contacts) {
  implicit_forces(m, s, h, &contacts, work_);
  const auto v = s.v();
  Real worst = 0, heaviest = 0;
  for (const std::uint32_t i : free_) {
    const Real mass = m.points.mass[i];
    const Vec3 r = (v[i] - vn_[i]) * (mass / h) - explicit_[i] - work_[i];
    worst = std::max(worst, norm(r));
    heaviest = std::max(heaviest, mass);
  }
  const Real g = norm(m.fields.gravity) > 0 ? norm(m.fields.gravity) : Real(9.81);
  return heaviest > 0 ? double(worst / (heaviest * g)) : 0.0;
}

}  // namespace maille
