#include "contact_entry.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "implicit_vbd.hpp"  // kVbdBisections, kVbdMaxSegmentSamples

namespace maille {

void ContactEntry::begin(std::span<PointContacts* const> contacts, const Vec3* xn,
                         std::size_t points) {
  contacts_.assign(contacts.begin(), contacts.end());
  xn_ = xn;
  thinnest_ = std::numeric_limits<Real>::infinity();
  for (const PointContacts* c : contacts_) thinnest_ = std::min(thinnest_, c->thickness());
  if (x_.size() != points) {
    x_.assign(points, Vec3{});
    v_.assign(points, Vec3{});
    g_.assign(points, Vec3{});
    h_.assign(points, Mat3{});
    touch_.assign(points, 0);
  }
}

// Whether point i touches a contact at `at` with velocity `vel`; its push in g_[i].
bool ContactEntry::touches(std::uint32_t i, const Vec3& at, const Vec3& vel, Real inv_h) {
  const std::span<const std::uint32_t> one(&i, 1);
  x_[i] = at;
  v_[i] = vel;
  touch_[i] = 0;
  g_[i] = Vec3{};
  for (const PointContacts* c : contacts_)
    c->add_terms(one, x_.data(), v_.data(), inv_h, g_.data(), h_.data(), touch_.data());
  return touch_[i] != 0;
}

// Sampled at half the thinnest contact region (x_n included: a point already touching a thin
// box and heading through it stays), then bisected between the last sample that does not
// enter and the first that does.
Real ContactEntry::first_touch(std::uint32_t i, const Vec3& to, Real h, bool through_only) {
  const Vec3 from = xn_[i], d = to - from;
  const Real inv_h = Real(1) / h;
  auto at = [&](Real t) {
    const Vec3 p = from + d * t;
    return touches(i, p, (p - xn_[i]) * inv_h, inv_h);
  };
  auto enters = [&](Real t) { return at(t) && dot(g_[i], d) < 0; };
  if (through_only && at(1)) return 1;
  bool before = at(0);
  if (before && dot(g_[i], d) < 0) return 0;
  const Real length = norm(d);
  const int samples = int(std::min<Real>(kVbdMaxSegmentSamples, std::ceil(2 * length / thinnest_)));
  for (int k = 1; k <= samples; ++k) {
    const Real t = Real(k) / Real(samples);
    const bool from_outside = !before;
    before = at(t);
    // Entering: touching after a sample outside (whatever the push: inside a thin box mapped
    // canonically, the push may point to a side face), or pushed against the motion.
    if (!before || !(from_outside || dot(g_[i], d) < 0)) continue;
    Real lo = Real(k - 1) / Real(samples), hi = t;
    for (int b = 0; b < kVbdBisections; ++b) {
      const Real mid = Real(0.5) * (lo + hi);
      ((from_outside ? at(mid) : enters(mid)) ? hi : lo) = mid;
    }
    return hi;
  }
  return 1;
}

void ContactEntry::stop_at_first_touch(std::span<const std::uint32_t> points, Vec3* x, Vec3* v,
                                       Real h, bool through_only) {
  if (!(thinnest_ < std::numeric_limits<Real>::infinity())) return;
  const Real half = Real(0.5) * thinnest_;
  for (const std::uint32_t i : points) {
    if (norm2(x[i] - xn_[i]) <= half * half) continue;
    const Real t = first_touch(i, x[i], h, through_only);
    if (t >= 1) continue;
    x[i] = xn_[i] + (x[i] - xn_[i]) * t;
    v[i] = (x[i] - xn_[i]) * (Real(1) / h);
  }
}

void ContactEntry::stop_at_entry(std::span<const std::uint32_t> points, Vec3* x, Vec3* v, Real h) {
  stop_at_first_touch(points, x, v, h, false);
  if (contacts_.empty()) return;
  const Real inv_h = Real(1) / h;
  for (const std::uint32_t i : points) {
    const Vec3 from = xn_[i], d = x[i] - from;
    auto at = [&](Real t) { return touches(i, from + d * t, d * (t * inv_h), inv_h); };
    if (at(0) || !at(1)) continue;
    Real lo = 0, hi = 1;
    for (int b = 0; b < kVbdBisections; ++b) {
      const Real mid = Real(0.5) * (lo + hi);
      (at(mid) ? hi : lo) = mid;
    }
    x[i] = from + d * hi;
    v[i] = (x[i] - from) * inv_h;
  }
}

}  // namespace maille
