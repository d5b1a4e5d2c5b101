#include "drift_guard.hpp"

#include <algorithm>
#include <cmath>

#include "maille/shared_laws.hpp"

namespace maille {

void DriftGuard::take_limits(std::span<TriangleContacts* const> stencils, const Model& m) {
  const std::size_t n = m.points.size();
  limit_.assign(n, kUnguarded);
  held_.assign(n, 0);
  guarded_.clear();
  anchors_.clear();
  anchor_limit_ = kUnguarded;
  active_ = false;
  std::vector<std::uint8_t>& anchor = held_;  // a scratch mask until the end
  for (const TriangleContacts* t : stencils) {
    const Real limit = t->drift_limit();
    if (!(limit < kUnguarded)) continue;
    active_ = true;
    for (const std::uint32_t p : t->points()) {
      if (m.points.inv_mass[p] > 0) {
        limit_[p] = std::min(limit_[p], limit);
      } else {
        anchor[p] = 1;
        anchor_limit_ = std::min(anchor_limit_, limit);
      }
    }
  }
  for (std::uint32_t p = 0; p < n; ++p) {
    if (limit_[p] < kUnguarded) guarded_.push_back(p);
    if (anchor[p]) anchors_.push_back(p);
  }
  std::fill(held_.begin(), held_.end(), 0);
}

void DriftGuard::first_search(std::span<TriangleContacts* const> stencils, const Model& m,
                              const Vec3* x, const Vec3* v, Real h) {
  take_limits(stencils, m);
  searches_again_ = 0;
  common_ = Vec3{};
  predicted_.resize(limit_.size());
  for (const std::uint32_t p : guarded_) predicted_[p] = x[p] + v[p] * h;
  // A driven point stays at x_n inside the solve and takes its drive's move at the next step's
  // start, before the next search: over that interval it is where its velocity predicts (its
  // drift nothing but the drive's curvature), so it enters the common part with none.
  for (const std::uint32_t p : anchors_) predicted_[p] = x[p];
}

void DriftGuard::searched_again(const Vec3* x) {
  // The stages, their limits and points are the step's: only the predictions start again.
  for (const std::uint32_t p : guarded_) held_[p] = 0;
  ++searches_again_;
  common_ = Vec3{};
  predicted_.resize(limit_.size());
  for (const std::uint32_t p : guarded_) predicted_[p] = x[p];
  for (const std::uint32_t p : anchors_) predicted_[p] = x[p];
}

std::span<const std::uint32_t> DriftGuard::moved(const Vec3* x) {
  moved_.clear();
  for (const std::uint32_t p : guarded_) {
    const Real renew = kRenewShare * limit_[p];
    if (!held_[p] && norm2(x[p] - predicted_[p] - common_) <= renew * renew) continue;
    if (double(moved_.size() + 1) > kNearShare * double(guarded_.size())) {
      moved_.clear();
      break;
    }
    moved_.push_back(p);
  }
  return moved_;
}

void DriftGuard::searched_near(const Vec3* x) {
  for (const std::uint32_t p : moved_) {
    held_[p] = 0;
    predicted_[p] = x[p] - common_;  // its ball about x: the common part is everyone's
  }
  ++searches_again_;
}

void DriftGuard::take_common(const Vec3* x) {
  common_ = Vec3{};
  if (!active_ || guarded_.empty()) return;
  Vec3 lo = x[guarded_.front()] - predicted_[guarded_.front()], hi = lo;
  auto widen = [&](std::uint32_t p) {
    const Vec3 d = x[p] - predicted_[p];
    lo = {std::min(lo.x, d.x), std::min(lo.y, d.y), std::min(lo.z, d.z)};
    hi = {std::max(hi.x, d.x), std::max(hi.y, d.y), std::max(hi.z, d.z)};
  };
  for (const std::uint32_t p : guarded_) widen(p);
  for (const std::uint32_t p : anchors_) widen(p);
  common_ = (lo + hi) * Real(0.5);
  // The anchors do not move with the common part: each stays within its limit of it only while
  // |c| is at most that limit (their drift is zero). A wider box (a free point that would fall
  // far in one step past a fixed one) then holds the free points and makes a search due, as the
  // argument needs: with c at the box's centre, a bead thrown 1.4 m in a step of 1/60 s had its
  // ball 0.7 m down, through the fixed cloth below it.
  const Real c = norm(common_);
  if (!anchors_.empty() && c > anchor_limit_) common_ = common_ * (anchor_limit_ / c);
}

// The move held in the ball about the prediction (law::ball_hold, shared with the GPU's VBD).
Vec3 DriftGuard::held_move(std::uint32_t i, const Vec3& from, const Vec3& to) {
  held_[i] = 1;
  return law::ball_hold(from, to, from - predicted_[i] - common_, limit_[i]);
}

bool DriftGuard::search_due() const {
  for (const std::uint32_t p : guarded_)
    if (held_[p]) return true;
  return false;
}

}  // namespace maille
