// Self-collision's point-triangle and edge-edge contacts inside implicit solves
// (TriangleContacts, stage.hpp): the candidates the stage found at the step's start, and the
// contact's energy terms evaluated at any iterate, with the closest points found again each time
// (include/maille/detail/contact_laws.glsl).
#pragma once

#include <array>
#include <cstdint>
#include <limits>
#include <span>
#include <vector>

#include "maille/mat3.hpp"
#include "maille/stage.hpp"

namespace maille::collision {

class TriangleContactTerms final : public TriangleContacts {
 public:
  // The law: contact radius s, stiffness k, damping z, friction mu (lagged: lag()).
  void set_law(Real radius, Real stiffness, Real damping, Real friction) {
    radius_ = radius;
    stiffness_ = stiffness;
    damping_ = damping;
    friction_ = friction;
  }
  // The friction's lag, at the step's start (x_n, v_n), after the candidates are stored: each
  // acting candidate's normal and normal force are held for the solve (IPC's lagged friction,
  // as obstacles and point-point contacts do), so that its Coulomb friction, -mu F_n v_t /
  // max(|v_t|, slip) on the particle (v_t across the held normal, v the particle's velocity
  // less the closest point's), is a smooth term of the solve with the tangent block
  // c^2 mu F_n / max(|v_t|, slip) (I - n n^T) / h, its scale held. A candidate that acted at
  // the step's start keeps its friction through the step.
  void lag(const Vec3* x, const Vec3* v);
  // Filled by the stage each step: the point-triangle candidates ({particle, corners}, sorted
  // by particle), then from edge_begin() on the edge-edge ones ({a0, a1, b0, b1}).
  std::vector<std::array<std::uint32_t, 4>>& storage() { return candidates_; }
  void set_edge_begin(std::size_t e) { edge_begin_ = e; }
  // The edge pairs' corners that are colliding particles, bit j for corner j (from edge_begin()
  // on: law::edge_edge_acts), filled with them.
  std::vector<std::uint8_t>& edge_particles() { return edge_particles_; }
  std::size_t edge_begin() const { return edge_begin_; }
  // The law and each candidate's lag and corners, as a device uploads them (the GPU's VBD).
  Real stiffness() const { return stiffness_; }
  Real damping() const { return damping_; }
  Real friction() const { return friction_; }
  Real lag_force(std::size_t e) const { return e < lag_force_.size() ? lag_force_[e] : Real(0); }
  Vec3 lag_normal(std::size_t e) const { return e < lag_normal_.size() ? lag_normal_[e] : Vec3{}; }
  std::uint8_t edge_particle_bits(std::size_t e) const { return edge_particles_[e - edge_begin_]; }

  // The candidates acting at (x, v): {point-triangle, edge-edge} (the stage's counters).
  std::array<std::size_t, 2> touching(const Vec3* x, const Vec3* v) const;

  std::span<const std::array<std::uint32_t, 4>> candidates() const override { return candidates_; }
  void accumulate(const Vec3* x, const Vec3* v, Vec3* f) const override;
  Real distance(std::size_t e, const Vec3* x) const override;
  Real radius() const override { return radius_; }
  bool held(std::size_t e) const override {
    return friction_ > 0 && e < lag_force_.size() && lag_force_[e] > 0;
  }
  void add_point_terms(std::span<const std::uint32_t> points, const std::uint32_t* row,
                       const std::uint32_t* entries, const Vec3* x, const Vec3* v, Real inv_h,
                       Vec3* f, Mat3* hessian) const override;
  void set_sweep_start(const Vec3* x, const Real* distances) override {
    start_x_ = x;
    start_distance_ = distances;
  }
  void linearise(const Vec3* x, const Vec3* v) override;
  void apply(Real a, Real b, const Vec3* u, Vec3* out) const override;
  void add_diagonal(Real a, Real b, Mat3* diagonal) const override;
  void couplings(Real a, Real b, std::vector<StencilCoupling>& out) const override;
  // The search's guarantee, set by the stage with each search (TriangleContacts).
  void set_drift(Real limit, std::span<const std::uint32_t> points) {
    drift_limit_ = limit;
    points_ = points;
  }
  Real drift_limit() const override { return drift_limit_; }
  std::span<const std::uint32_t> points() const override { return points_; }

 private:
  // Candidate e at x, v: whether it acts (closer than s, not a shared feature counted by an
  // earlier candidate of its particle), and then its normal, coefficients and force.
  struct Eval {
    Vec3 n{}, force{};  // the normal (when `touching`) and the force on the particle
    std::array<Real, 4> c{};
    bool touching = false;  // within s (else only the lagged friction acts)
    Real friction = 0;      // the friction's scale mu F_n / max(|v_t|, slip), held
  };
  bool evaluate(std::size_t e, const Vec3* x, const Vec3* v, Eval& out) const;
  bool finish(std::size_t e, const Vec3& d, Real d2, bool rubbing, const Vec3* v, Eval& out) const;

  Real radius_ = 0, stiffness_ = 0, damping_ = 0, friction_ = 0;
  Real drift_limit_ = std::numeric_limits<Real>::infinity();
  std::span<const std::uint32_t> points_;
  std::vector<std::array<std::uint32_t, 4>> candidates_;
  // candidates_ from here on are edge pairs (none until the stage says where they start)
  std::size_t edge_begin_ = std::numeric_limits<std::size_t>::max();
  std::vector<std::uint8_t> edge_particles_;  // [candidates - edge_begin_]
  std::vector<Real> lag_force_;   // [candidates] |F_n| at the step's start (0: no friction)
  std::vector<Vec3> lag_normal_;  // [candidates] n at the step's start
  struct Active {
    std::uint32_t e;
    Vec3 n;
    std::array<Real, 4> c;
    bool touching;
    Real friction;
  };
  Mat3 block(const Active& ac, Real s, Real b) const;
  std::vector<Active> active_;  // linearise's contacts
  bool far_since_start(std::size_t e, const Vec3* x) const;
  const Vec3* start_x_ = nullptr;  // set_sweep_start
  const Real* start_distance_ = nullptr;
};

}  // namespace maille::collision
