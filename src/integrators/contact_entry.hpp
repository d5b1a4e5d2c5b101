// Internal: continuous detection against a step's point contacts (obstacles, conditional
// shells: PointContacts, stage.hpp). A point whose move over a step is longer than half the
// thinnest contact region could cross one unseen; this finds where on its segment from x_n it
// first enters one. Vertex block descent uses it on its initial guess and its result; the CG
// solvers on their solved step, whose one linearisation at x_n does not see a contact the step
// enters.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "maille/mat3.hpp"
#include "maille/stage.hpp"

namespace maille {

class ContactEntry {
 public:
  // The step's contacts and its start positions (read through the pointer until the step
  // ends), for `points` points.
  void begin(std::span<PointContacts* const> contacts, const Vec3* xn, std::size_t points);
  // The thinnest contact region (PointContacts::thickness), +inf with no contact.
  Real thinnest() const { return thinnest_; }

  // Fraction of the segment x_n,i -> `to` at which point i first enters a contact: touches it
  // after a sample outside, or while moving against its push (a point leaving a contact, or
  // sliding along one, is not stopped), just inside it. 1: it enters nothing on the way, or,
  // with through_only, it touches at `to` (the solve saw that contact). Uses point i's working
  // values only (threads may run other points).
  Real first_touch(std::uint32_t i, const Vec3& to, Real h, bool through_only);
  // Points of `points` that moved more than half the thinnest contact region stop at their first
  // touch (v follows: (x - x_n) / h).
  void stop_at_first_touch(std::span<const std::uint32_t> points, Vec3* x, Vec3* v, Real h,
                           bool through_only);
  // The same (not through_only); then a point that ends inside a contact it did not touch at x_n
  // (a half-space entered at speed) stops just inside where it entered.
  void stop_at_entry(std::span<const std::uint32_t> points, Vec3* x, Vec3* v, Real h);

 private:
  bool touches(std::uint32_t i, const Vec3& at, const Vec3& vel, Real inv_h);

  std::vector<PointContacts*> contacts_;
  const Vec3* xn_ = nullptr;
  Real thinnest_ = 0;
  // One point's trial position, velocity and contact terms (point i's slot only).
  std::vector<Vec3> x_, v_, g_;
  std::vector<Mat3> h_;
  std::vector<std::uint8_t> touch_;
};

}  // namespace maille
