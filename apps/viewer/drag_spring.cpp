#include "drag_spring.hpp"

#include <algorithm>
#include <cmath>

namespace maille::viewer {

void DragState::grab(const DragTarget& t) {
  std::lock_guard lock(mutex_);
  drag_ = t;
}

void DragState::move_to(const Vec3& target) {
  std::lock_guard lock(mutex_);
  if (drag_) drag_->target = target;
}

void DragState::release() {
  std::lock_guard lock(mutex_);
  drag_.reset();
}

std::optional<DragTarget> DragState::current() const {
  std::lock_guard lock(mutex_);
  return drag_;
}

void DragSpring::apply(const Model& m, State& s, const StageContext&) {
  const auto d = state_->current();
  if (!d || d->point >= s.size() || m.points.inv_mass[d->point] == 0) return;
  const Vec3 x = s.x()[d->point], v = s.v()[d->point];
  s.f()[d->point] += (d->target - x) * d->stiffness - v * d->damping;
}

DragTarget default_drag(const Model& m, double step, std::uint32_t point, const Vec3& target) {
  Real free_mass = 0;
  for (std::uint32_t i = 0; i < m.points.size(); ++i)
    if (m.points.inv_mass[i] > 0) free_mass += m.points.mass[i];
  const Real g = std::max<Real>(norm(m.fields.gravity), Real(1));
  // The whole weight held with 5 cm of stretch...
  Real k = free_mass * g / Real(0.05);
  // ...but the particle alone on this spring must stay well inside the explicit step's limit
  // (omega h < 2 for leapfrog): omega h <= 0.5.
  const Real mi = m.points.mass[point];
  const Real h = Real(step);
  k = std::min(k, mi * Real(0.25) / (h * h));
  // Critically damped for the particle alone, so it follows the mouse without ringing.
  const Real c = std::min(2 * std::sqrt(k * mi), Real(0.5) * mi / h);
  return {point, target, k, c};
}

}  // namespace maille::viewer
