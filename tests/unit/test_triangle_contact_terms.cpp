// The point-triangle contact terms that implicit solves use (triangle_contact_terms.hpp) are the
// explicit self-collision force without friction, at any configuration: on a face, on an edge
// shared by two triangles and on a corner shared by six (each pushed once), and their stiffness
// blocks are the force's derivative along the normal.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "collision/self/triangle_contact_terms.hpp"
#include "collision/self/triangle_proximity.hpp"
#include "maille/model.hpp"

namespace {

using namespace maille;

constexpr Real kRadius = Real(0.03), kStiffness = 200, kDamping = Real(0.5);

// A 3 x 3 grid of points in the plane y = 0 (spacing 0.1, two triangles per cell), and three
// particles above it: over a face, over the inner edge of a cell, over the middle corner.
struct Sheet {
  Model m;
  std::vector<Vec3> x, v;
  Sheet() {
    for (int j = 0; j < 3; ++j)
      for (int i = 0; i < 3; ++i)
        m.points.add(PointKind::free, 1, {Real(0.1) * i, 0, Real(0.1) * j});
    for (std::uint32_t j = 0; j < 2; ++j)
      for (std::uint32_t i = 0; i < 2; ++i) {
        const std::uint32_t a = j * 3 + i, b = a + 1, c = a + 3, d = a + 4;
        m.surface.triangles.push_back({a, b, d});
        m.surface.triangles.push_back({a, d, c});
      }
    for (const Vec3 p : {Vec3{Real(0.07), Real(0.02), Real(0.02)},   // face
                         Vec3{Real(0.05), Real(0.015), Real(0.05)},  // the diagonal edge
                         Vec3{Real(0.1), Real(0.01), Real(0.1)}})    // the middle corner
      m.points.add(PointKind::free, 1, p);
    for (std::uint32_t i = 0; i < m.points.size(); ++i) {
      x.push_back(m.points.initial_position[i]);
      v.push_back({Real(0.01) * Real(i % 3), -Real(0.2), Real(0.03) * Real(i % 2)});
    }
  }
};

struct Contacts {
  Sheet s;
  std::vector<std::uint32_t> set;
  std::vector<std::uint8_t> mask;
  collision::TriangleProximity prox;
  collision::TriangleContactTerms terms;
  Contacts()
      : set(all(s.m)), mask(s.m.points.size(), 1), prox(s.m, set, mask, std::size_t{1} << 20) {
    terms.set_law(kRadius, kStiffness, kDamping, 0);
    prox.candidates(s.x.data(), s.v.data(), kRadius, Real(0.01), Real(0.05), nullptr, 1,
                    terms.storage());
  }
  static std::vector<std::uint32_t> all(const Model& m) {
    std::vector<std::uint32_t> v(m.points.size());
    for (std::uint32_t i = 0; i < v.size(); ++i) v[i] = i;
    return v;
  }
  // Rows by point, as the solvers build them.
  void rows(std::vector<std::uint32_t>& row, std::vector<std::uint32_t>& entries) const {
    const auto c = terms.candidates();
    const std::size_t n = s.m.points.size();
    std::vector<std::vector<std::uint32_t>> by(n);
    for (std::size_t e = 0; e < c.size(); ++e)
      for (std::uint32_t r = 0; r < 4; ++r) by[c[e][r]].push_back(std::uint32_t(4 * e + r));
    row.assign(1, 0);
    for (const auto& list : by) {
      entries.insert(entries.end(), list.begin(), list.end());
      row.push_back(std::uint32_t(entries.size()));
    }
  }
};

TEST(TriangleContactTerms, AreTheExplicitForceWithoutFriction) {
  Contacts t;
  const std::size_t n = t.s.m.points.size();
  std::vector<Vec3> explicit_f(n), terms_f(n), point_f(n);
  std::vector<Mat3> hessian(n);
  const std::uint64_t contacts = t.prox.apply(t.s.x.data(), t.s.v.data(), explicit_f.data(),
                                              {kRadius, kStiffness, kDamping, 0}, nullptr, 1);
  EXPECT_EQ(contacts, 3u);  // one per particle: the edge and the corner are pushed once
  t.terms.accumulate(t.s.x.data(), t.s.v.data(), terms_f.data());
  std::vector<std::uint32_t> row, entries;
  t.rows(row, entries);
  const std::vector<std::uint32_t> points = Contacts::all(t.s.m);
  t.terms.add_point_terms(points, row.data(), entries.data(), t.s.x.data(), t.s.v.data(), 0,
                          point_f.data(), hessian.data());
  Real largest = 0;
  for (const Vec3& f : explicit_f) largest = std::max(largest, norm(f));
  ASSERT_GT(largest, 1);
  // The same terms summed in another order: rounding only.
  for (std::size_t i = 0; i < n; ++i) {
    EXPECT_LT(norm(terms_f[i] - explicit_f[i]), 1e-12 * largest) << "point " << i;
    EXPECT_LT(norm(point_f[i] - explicit_f[i]), 1e-12 * largest) << "point " << i;
  }
  // The particles over the edge and the corner: pushed straight up by one contact's law.
  for (std::uint32_t p : {10u, 11u}) {
    const Real d = t.s.x[p].y;
    const Real want = kStiffness * (kRadius - d) - kDamping * t.s.v[p].y;  // corners' v: -0.2 too
    EXPECT_NEAR(explicit_f[p].y, want + kDamping * (-Real(0.2)), 1e-9) << "particle " << p;
  }
}

// With friction, lagged at the step's start: there the terms are the explicit force, friction
// included (the solvers take the stage's start-of-step force back out through them); a
// candidate in contact at the start keeps its friction when the particle leaves the face, with
// the tangent block mu F_n / max(|v_t|, slip) (I - n n^T) / h.
TEST(TriangleContactTerms, AreTheExplicitForceWithLaggedFrictionAtTheStepStart) {
  Contacts t;
  const Real mu = Real(0.5), inv_h = 60;
  t.terms.set_law(kRadius, kStiffness, kDamping, mu);
  t.terms.lag(t.s.x.data(), t.s.v.data());
  const std::size_t n = t.s.m.points.size();
  std::vector<Vec3> explicit_f(n), terms_f(n), point_f(n);
  std::vector<Mat3> hessian(n);
  t.prox.apply(t.s.x.data(), t.s.v.data(), explicit_f.data(), {kRadius, kStiffness, kDamping, mu},
               nullptr, 1);
  t.terms.accumulate(t.s.x.data(), t.s.v.data(), terms_f.data());
  std::vector<std::uint32_t> row, entries;
  t.rows(row, entries);
  const std::vector<std::uint32_t> points = Contacts::all(t.s.m);
  t.terms.add_point_terms(points, row.data(), entries.data(), t.s.x.data(), t.s.v.data(), inv_h,
                          point_f.data(), hessian.data());
  Real largest = 0, tangential = 0;
  for (const Vec3& f : explicit_f) largest = std::max(largest, norm(f));
  for (std::uint32_t p : {9u, 10u, 11u})
    tangential = std::max(tangential, std::hypot(explicit_f[p].x, explicit_f[p].z));
  ASSERT_GT(tangential, Real(1e-3) * largest);  // friction acts (the particles slide)
  for (std::size_t i = 0; i < n; ++i) {
    EXPECT_LT(norm(terms_f[i] - explicit_f[i]), 1e-12 * largest) << "point " << i;
    EXPECT_LT(norm(point_f[i] - explicit_f[i]), 1e-12 * largest) << "point " << i;
  }
  // The particle over the face lifted out of reach: its friction stays, along -v_t, and its
  // block has a tangent part.
  auto x = t.s.x;
  x[9].y = 2 * kRadius;
  std::vector<Vec3> f(n);
  std::vector<Mat3> h(n);
  const std::uint32_t one[] = {9u};
  t.terms.add_point_terms(one, row.data(), entries.data(), x.data(), t.s.v.data(), inv_h, f.data(),
                          h.data());
  EXPECT_GT(norm(f[9]), 0);
  EXPECT_LT(dot(f[9], Vec3{t.s.v[9].x, 0, t.s.v[9].z}), 0);
  EXPECT_GT(dot(h[9] * Vec3{1, 0, 0}, Vec3{1, 0, 0}), 0);
}

// -d f_i / d x_i along the contact normal is the block's n^T H n (inv_h = 0: stiffness only).
// For the particle it is exactly k. A corner j's block k w_j^2 is the Gauss-Newton part: moving a
// corner also tilts the face and shifts the closest point, terms proportional to the contact
// force that the solvers leave out (they may be indefinite); the particle over the face here
// just touches it (force k 1e-4 m), so they are under 1 % of k.
TEST(TriangleContactTerms, StiffnessBlocksAreTheForcesDerivative) {
  Contacts t;
  const std::size_t n = t.s.m.points.size();
  t.s.x[9].y = kRadius - Real(1e-4);
  auto& cand = t.terms.storage();  // the face particle's candidates only
  std::erase_if(cand, [](const auto& c) { return c[0] != 9; });
  ASSERT_FALSE(cand.empty());
  std::vector<std::uint32_t> row, entries;
  t.rows(row, entries);
  std::vector<Vec3> zero_v(n);
  auto force_on = [&](std::uint32_t i, const std::vector<Vec3>& x) {
    std::vector<Vec3> f(n);
    std::vector<Mat3> h(n);
    const std::uint32_t one[] = {i};
    t.terms.add_point_terms(one, row.data(), entries.data(), x.data(), zero_v.data(), 0, f.data(),
                            h.data());
    return std::pair{f[i], h[i]};
  };
  const Vec3 up{0, 1, 0};
  const Real eps = Real(1e-7);
  for (std::uint32_t i : {9u, 0u, 1u, 4u}) {  // the particle, then the corners of its face
    auto plus = t.s.x, minus = t.s.x;
    plus[i] += up * eps;
    minus[i] -= up * eps;
    const Real derivative =
        -dot(force_on(i, plus).first - force_on(i, minus).first, up) / (2 * eps);
    const Real block = dot(force_on(i, t.s.x).second * up, up);
    EXPECT_NEAR(block, derivative, (i == 9 ? 1e-5 : 1e-2) * kStiffness) << "point " << i;
    EXPECT_GT(block, 0) << "point " << i;
  }
  EXPECT_NEAR(dot(force_on(9, t.s.x).second * up, up), kStiffness, 1e-9 * kStiffness);
}

}  // namespace

// The explicit pass keeps its particle-triangle pairs while nothing has moved half the skin
// (triangle_proximity.hpp): its contacts and forces equal, bit for bit, those of a pass that
// finds them afresh, step after step, while particles slide over a fine rippling sheet
// (triangles smaller than the radius, so that new ones come within it at every step; the list
// kept for a few steps, then found again). Loosening the rule to 4 times the skin fails it.
TEST(TriangleProximity, KeptListGivesTheFreshSearchesForces) {
  constexpr int kSide = 12;
  constexpr Real kSpacing = Real(0.02);
  Model m;
  for (int j = 0; j < kSide; ++j)
    for (int i = 0; i < kSide; ++i)
      m.points.add(PointKind::free, 1, {kSpacing * i, 0, kSpacing * j});
  for (std::uint32_t j = 0; j + 1 < kSide; ++j)
    for (std::uint32_t i = 0; i + 1 < kSide; ++i) {
      const std::uint32_t a = j * kSide + i, b = a + 1, c = a + kSide, d = c + 1;
      m.surface.triangles.push_back({a, b, d});
      m.surface.triangles.push_back({a, d, c});
    }
  for (int k = 0; k < 5; ++k)
    m.points.add(PointKind::free, 1,
                 {Real(0.2) + Real(0.007) * k, Real(0.004) * k, Real(0.03) * k});
  std::vector<Vec3> x(m.points.initial_position.begin(), m.points.initial_position.end());
  std::vector<Vec3> v(x.size(), Vec3{Real(-0.3), 0, Real(0.1)});
  const std::vector<std::uint32_t> set = Contacts::all(m);
  const std::vector<std::uint8_t> mask(m.points.size(), 1);
  collision::TriangleProximity kept(m, set, mask, std::size_t{1} << 20);
  const collision::TriangleResponse law{kRadius, kStiffness, kDamping, Real(0.3)};
  const auto sheet = std::uint32_t(kSide * kSide);
  std::uint64_t touched = 0;
  for (int step = 0; step < 40; ++step) {
    for (std::uint32_t i = 0; i < x.size(); ++i)
      x[i] += i >= sheet ? Vec3{Real(-0.004), Real(-0.0002), Real(0.0013)}
                         : Vec3{0, Real(0.0005) * std::sin(Real(step + i)), 0};
    std::vector<Vec3> f_kept(x.size()), f_fresh(x.size());
    collision::TriangleProximity fresh(m, set, mask, std::size_t{1} << 20);
    const std::uint64_t a = kept.apply(x.data(), v.data(), f_kept.data(), law, nullptr, 1);
    const std::uint64_t b = fresh.apply(x.data(), v.data(), f_fresh.data(), law, nullptr, 1);
    ASSERT_EQ(a, b) << "step " << step;
    for (std::size_t i = 0; i < x.size(); ++i) {
      ASSERT_EQ(f_kept[i].x, f_fresh[i].x) << "step " << step << " point " << i;
      ASSERT_EQ(f_kept[i].y, f_fresh[i].y) << "step " << step << " point " << i;
      ASSERT_EQ(f_kept[i].z, f_fresh[i].z) << "step " << step << " point " << i;
    }
    touched += a;
  }
  // Contacts every step: with no exclusion, the sheet's points touch their neighbours' faces too.
  EXPECT_GT(touched, 100u);
}

// A sweep's start lets the terms skip the candidates still farther than the radius (their
// points moved less than the distance's excess since): the forces and blocks are the same bits
// as without it, whether the particles stayed, came closer by a little (still apart) or came
// into contact (a candidate skipped wrongly would lose its force); and with start distances that
// say every candidate was far, it does skip them.
TEST(TriangleContactTerms, ASweepStartSkipsOnlyCandidatesThatCannotTouch) {
  Contacts t;
  const Real inv_h = 60;
  const std::size_t n = t.s.m.points.size();
  std::vector<Real> start_distance;
  for (std::size_t e = 0; e < t.terms.candidates().size(); ++e)
    start_distance.push_back(t.terms.distance(e, t.s.x.data()));
  std::vector<std::uint32_t> row, entries;
  t.rows(row, entries);
  const std::vector<std::uint32_t> points = Contacts::all(t.s.m);
  // The three particles lifted to 2.5 radii above the sheet, then lowered by 0, 1 and 2 radii.
  std::vector<Vec3> start = t.s.x;
  for (std::uint32_t p : {9u, 10u, 11u}) start[p].y = Real(2.5) * kRadius;
  for (std::size_t e = 0; e < start_distance.size(); ++e)
    start_distance[e] = t.terms.distance(e, start.data());
  int touching_somewhere = 0;
  for (const Real drop : {Real(0), kRadius, 2 * kRadius}) {
    std::vector<Vec3> x = start;
    for (std::uint32_t p : {9u, 10u, 11u}) x[p].y -= drop;
    std::vector<Vec3> f0(n), f1(n);
    std::vector<Mat3> h0(n), h1(n);
    t.terms.add_point_terms(points, row.data(), entries.data(), x.data(), t.s.v.data(), inv_h,
                            f0.data(), h0.data());
    t.terms.set_sweep_start(start.data(), start_distance.data());
    t.terms.add_point_terms(points, row.data(), entries.data(), x.data(), t.s.v.data(), inv_h,
                            f1.data(), h1.data());
    t.terms.set_sweep_start(nullptr, nullptr);
    for (std::size_t i = 0; i < n; ++i) {
      EXPECT_EQ(f0[i].x, f1[i].x) << "drop " << drop << " point " << i;
      EXPECT_EQ(f0[i].y, f1[i].y) << "drop " << drop << " point " << i;
      EXPECT_EQ(f0[i].z, f1[i].z) << "drop " << drop << " point " << i;
      for (int r = 0; r < 3; ++r)
        for (int c = 0; c < 3; ++c) EXPECT_EQ(h0[i].m[r][c], h1[i].m[r][c]);
    }
    const bool touching = norm(f0[9]) > 0;
    touching_somewhere += touching ? 1 : 0;
  }
  EXPECT_EQ(touching_somewhere, 1);  // only the last drop (to half a radius) touches
  // The skip acts: told that every candidate started far beyond its reach, the terms leave out
  // the touching ones too (a gate that never skipped would pass the comparisons above).
  std::vector<Vec3> x = start;
  for (std::uint32_t p : {9u, 10u, 11u}) x[p].y -= 2 * kRadius;
  const std::vector<Real> far(start_distance.size(), Real(1e3));
  std::vector<Vec3> f(n);
  std::vector<Mat3> h(n);
  t.terms.set_sweep_start(start.data(), far.data());
  t.terms.add_point_terms(points, row.data(), entries.data(), x.data(), t.s.v.data(), inv_h,
                          f.data(), h.data());
  t.terms.set_sweep_start(nullptr, nullptr);
  for (std::size_t i = 0; i < n; ++i) EXPECT_EQ(norm(f[i]), 0) << "point " << i;
}
