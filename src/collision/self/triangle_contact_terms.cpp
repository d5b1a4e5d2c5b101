#include "triangle_contact_terms.hpp"

#include <algorithm>
#include <cmath>

#include "maille/self_collision.hpp"
#include "maille/shared_laws.hpp"
#include "triangle_proximity.hpp"

namespace maille::collision {

namespace {

// The feature candidate `c`'s triangle touches at weights w (feature_of wants a triangle index:
// any value serves for edges and corners, which are named by their corners).
Feature feature(const std::array<std::uint32_t, 4>& c, const std::array<Real, 3>& w,
                std::uint32_t e) {
  return feature_of({c[1], c[2], c[3]}, e, w);
}

bool has_corner(const std::array<std::uint32_t, 4>& c, std::uint32_t p) {
  return c[1] == p || c[2] == p || c[3] == p;
}

// An edge pair's coefficients (1 - s, s, -(1 - t), -t) at x and its gap vector; `acts`: the
// pair pushes there (law::edge_edge_acts, `particles` its corners' bits).
Vec3 edge_gap(const std::array<std::uint32_t, 4>& c, const Vec3* x, std::uint8_t particles,
              std::array<Real, 4>& coef, bool& acts) {
  Real s = 0, t = 0;
  law::edge_edge_params(x[c[0]], x[c[1]], x[c[2]], x[c[3]], s, t);
  coef = {1 - s, s, -(1 - t), -t};
  acts = law::edge_edge_acts(s, t, particles & 1, particles & 2, particles & 4, particles & 8);
  return x[c[0]] * coef[0] + x[c[1]] * coef[1] + x[c[2]] * coef[2] + x[c[3]] * coef[3];
}

}  // namespace

bool TriangleContactTerms::evaluate(std::size_t e, const Vec3* x, const Vec3* v, Eval& out) const {
  const auto& c = candidates_[e];
  const bool rubbing = friction_ > 0 && e < lag_force_.size() && lag_force_[e] > 0;
  if (e >= edge_begin_) {  // an edge pair: its own contact only inside both segments
    bool acts = false;
    const Vec3 d = edge_gap(c, x, edge_particles_[e - edge_begin_], out.c, acts);
    const Real d2 = dot(d, d);
    out.touching = acts && d2 < radius_ * radius_ && d2 != 0;
    return finish(e, d, d2, rubbing, v, out);
  }
  const std::array<Real, 3> w = closest_weights(x[c[0]], x[c[1]], x[c[2]], x[c[3]]);
  const Vec3 d = x[c[0]] - (x[c[1]] * w[0] + x[c[2]] * w[1] + x[c[3]] * w[2]);
  const Real d2 = dot(d, d);
  out.touching = d2 < radius_ * radius_ && d2 != 0;
  // An edge or a corner shared with an earlier candidate of the same particle that touches it
  // too is that candidate's (the explicit force pushes once per feature, lowest triangle).
  if (out.touching) {
    const Feature f = feature(c, w, std::uint32_t(e));
    if (f.kind < 2)
      for (std::size_t o = e; o-- > 0 && candidates_[o][0] == c[0];) {
        const auto& other = candidates_[o];
        if (!has_corner(other, f.a) || (f.kind == 1 && !has_corner(other, f.b))) continue;
        const std::array<Real, 3> wo =
            closest_weights(x[other[0]], x[other[1]], x[other[2]], x[other[3]]);
        if (feature(other, wo, std::uint32_t(o)) == f) {
          out.touching = false;
          break;
        }
      }
  }
  out.c = {1, -w[0], -w[1], -w[2]};
  return finish(e, d, d2, rubbing, v, out);
}

// The force at gap d (d2 = |d|^2) with out.c and out.touching set: the penalty and damper while
// touching, the lagged friction while rubbing.
bool TriangleContactTerms::finish(std::size_t e, const Vec3& d, Real d2, bool rubbing,
                                  const Vec3* v, Eval& out) const {
  if (!out.touching && !rubbing) return false;
  const auto& c = candidates_[e];
  Vec3 dv{};
  for (std::size_t j = 0; j < 4; ++j) dv += v[c[j]] * out.c[j];
  out.force = Vec3{};
  if (out.touching) {
    out.n = d / std::sqrt(d2);
    out.force = law::stencil_contact_force(d, dv, stiffness_, damping_, radius_);
  }
  out.friction = 0;
  if (rubbing) {  // the explicit law's (triangle_proximity.cpp), its normal and F_n held
    const Vec3 n = lag_normal_[e];
    out.friction =
        law::lagged_friction_scale(Vec3{}, dv, n, friction_, lag_force_[e], kSelfCollisionSlip);
    out.force -= law::lagged_friction_force(Vec3{}, dv, n, out.friction);
  }
  return true;
}

void TriangleContactTerms::lag(const Vec3* x, const Vec3* v) {
  lag_force_.assign(candidates_.size(), 0);
  lag_normal_.assign(candidates_.size(), Vec3{});
  if (!(friction_ > 0)) return;
  Eval ev;
  for (std::size_t e = 0; e < candidates_.size(); ++e)
    if (evaluate(e, x, v, ev) && ev.touching) {
      lag_normal_[e] = ev.n;
      lag_force_[e] = std::abs(dot(ev.force, ev.n));
    }
}

Real TriangleContactTerms::distance(std::size_t e, const Vec3* x) const {
  const auto& c = candidates_[e];
  if (e >= edge_begin_) {  // the segments' distance, wherever their closest points lie
    std::array<Real, 4> coef{};
    bool acts = false;
    return norm(edge_gap(c, x, 0, coef, acts));
  }
  const std::array<Real, 3> w = closest_weights(x[c[0]], x[c[1]], x[c[2]], x[c[3]]);
  return norm(x[c[0]] - (x[c[1]] * w[0] + x[c[2]] * w[1] + x[c[3]] * w[2]));
}

std::array<std::size_t, 2> TriangleContactTerms::touching(const Vec3* x, const Vec3* v) const {
  std::array<std::size_t, 2> out{0, 0};
  Eval ev;
  for (std::size_t e = 0; e < candidates_.size(); ++e)
    if (evaluate(e, x, v, ev) && ev.touching) ++out[e >= edge_begin_ ? 1 : 0];
  return out;
}

void TriangleContactTerms::accumulate(const Vec3* x, const Vec3* v, Vec3* f) const {
  Eval ev;
  for (std::size_t e = 0; e < candidates_.size(); ++e)
    if (evaluate(e, x, v, ev))
      for (std::size_t j = 0; j < 4; ++j) f[candidates_[e][j]] += ev.force * ev.c[j];
}

void TriangleContactTerms::add_point_terms(std::span<const std::uint32_t> points,
                                           const std::uint32_t* row, const std::uint32_t* entries,
                                           const Vec3* x, const Vec3* v, Real inv_h, Vec3* f,
                                           Mat3* hessian) const {
  const Real k = stiffness_ + damping_ * inv_h;
  Eval ev;
  for (const std::uint32_t i : points)
    for (std::uint32_t r = row[i]; r < row[i + 1]; ++r) {
      const std::uint32_t e = entries[r] / 4, role = entries[r] % 4;
      if (far_since_start(e, x) || !evaluate(e, x, v, ev)) continue;
      const Real c = ev.c[role];
      f[i] += ev.force * c;
      if (ev.touching) hessian[i] += Mat3::outer(ev.n, ev.n) * (k * c * c);
      if (ev.friction > 0) {
        const Vec3& n = lag_normal_[e];
        hessian[i] += (Mat3::identity() - Mat3::outer(n, n)) * (ev.friction * inv_h * c * c);
      }
    }
}

// Whether candidate e is still farther than the radius, known from the sweep's start alone: a
// feature's distance falls by at most the largest move of a point of each side, so by at most
// twice the largest move of its four points since the start (a relative 1e-9 for the rounding).
// Such a candidate gives no force (evaluate() would find it not touching) unless it holds a
// lagged friction.
bool TriangleContactTerms::far_since_start(std::size_t e, const Vec3* x) const {
  if (!start_x_ || held(e)) return false;
  const auto& c = candidates_[e];
  Real moved2 = 0;
  for (const std::uint32_t p : c) moved2 = std::max(moved2, norm2(x[p] - start_x_[p]));
  return start_distance_[e] - 2 * std::sqrt(moved2) >= radius_ * (1 + Real(1e-9));
}

void TriangleContactTerms::linearise(const Vec3* x, const Vec3* v) {
  active_.clear();
  Eval ev;
  for (std::size_t e = 0; e < candidates_.size(); ++e)
    if (evaluate(e, x, v, ev))
      active_.push_back({std::uint32_t(e), ev.n, ev.c, ev.touching, ev.friction});
}

void TriangleContactTerms::apply(Real a, Real b, const Vec3* u, Vec3* out) const {
  const Real s = a * stiffness_ + b * damping_;
  for (const Active& ac : active_) {
    const auto& c = candidates_[ac.e];
    Vec3 sum{};
    for (std::size_t j = 0; j < 4; ++j) sum += u[c[j]] * ac.c[j];
    Vec3 t = ac.touching ? ac.n * (s * dot(ac.n, sum)) : Vec3{};
    if (ac.friction > 0) {  // a damper of scale `friction` across the held normal
      const Vec3& n = lag_normal_[ac.e];
      t += (sum - n * dot(n, sum)) * (b * ac.friction);
    }
    for (std::size_t j = 0; j < 4; ++j) out[c[j]] += t * ac.c[j];
  }
}

// An active candidate's block B (block (i, j) of its stencil is c_i c_j B): s n n^T while
// touching (s = a k + b z), plus friction's damper b mu F_n / max(|v_t|, slip) across the held
// normal.
Mat3 TriangleContactTerms::block(const Active& ac, Real s, Real b) const {
  Mat3 out = ac.touching ? Mat3::outer(ac.n, ac.n) * s : Mat3{};
  if (ac.friction > 0) {
    const Vec3& n = lag_normal_[ac.e];
    out += (Mat3::identity() - Mat3::outer(n, n)) * (b * ac.friction);
  }
  return out;
}

void TriangleContactTerms::couplings(Real a, Real b, std::vector<StencilCoupling>& out) const {
  const Real s = a * stiffness_ + b * damping_;
  for (const Active& ac : active_) out.push_back({candidates_[ac.e], ac.c, block(ac, s, b)});
}

void TriangleContactTerms::add_diagonal(Real a, Real b, Mat3* diagonal) const {
  const Real s = a * stiffness_ + b * damping_;
  for (const Active& ac : active_) {
    const Mat3 stencil = block(ac, s, b);
    for (std::size_t j = 0; j < 4; ++j)
      diagonal[candidates_[ac.e][j]] += stencil * (ac.c[j] * ac.c[j]);
  }
}

}  // namespace maille::collision
