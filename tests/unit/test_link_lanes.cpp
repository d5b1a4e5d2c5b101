// VBD's link terms in lanes (LinkPool::axial_point_terms, axial_link_terms: kinds with
// K::axial, such as spring-dampers) against the kind's block taken link by link: the same
// forces and blocks bit for bit, in the sweeps' gather (a point's links in slot order) and in
// the coarse correction's scatter (every link once, in storage order). The random graph has
// stretched and compressed links (the definite block's clamp on both sides), zero and nonzero
// damping, and a hub point with more links than one run of lanes holds (its sums carried from
// one run to the next).
#include <gtest/gtest.h>

#include <random>
#include <vector>

#include "maille/link_loops.hpp"
#include "maille/link_pool.hpp"
#include "maille/links/spring_damper.hpp"

namespace maille {
namespace {

struct Links {
  LinkPool<SpringDamper> pool;
  std::vector<Vec3> x, v;
  std::vector<std::uint32_t> row, slots;  // each point's slots, in slot order (as VBD's rows)
};

Links random_links(std::uint32_t points, std::size_t count) {
  Links out;
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> unit(0, 1);
  for (std::uint32_t i = 0; i < points; ++i) {
    out.x.push_back(Vec3{unit(rng), unit(rng), unit(rng)} * Real(0.1));
    out.v.push_back(Vec3{unit(rng) - 0.5, unit(rng) - 0.5, unit(rng) - 0.5});
  }
  std::uniform_int_distribution<std::uint32_t> pick(0, points - 1);
  for (std::size_t l = 0; l < count; ++l) {
    // Point 0 is the hub: a quarter of the links (more than the 64 lanes of a run).
    const std::uint32_t a = l % 4 == 0 ? 0 : pick(rng);
    std::uint32_t b = pick(rng);
    if (b == a) b = (a + 1) % points;
    SpringDamper::Params p;
    p.stiffness = 10 + 3000 * unit(rng);
    p.rest_length = 0.01 + 0.1 * unit(rng);  // about half the links stretched
    p.damping = l % 3 == 0 ? 0 : 0.1 * unit(rng);
    out.pool.add({a, b}, p);
  }
  out.pool.prepare(points);
  const auto ends = out.pool.slot_ends();
  out.row.assign(points + 1, 0);
  for (const LinkEnds& e : ends) ++out.row[e.a + 1], ++out.row[e.b + 1];
  for (std::uint32_t i = 0; i < points; ++i) out.row[i + 1] += out.row[i];
  std::vector<std::uint32_t> cursor(out.row.begin(), out.row.end() - 1);
  out.slots.resize(out.row[points]);
  for (std::uint32_t l = 0; l < ends.size(); ++l) {
    out.slots[cursor[ends[l].a]++] = l;
    out.slots[cursor[ends[l].b]++] = l;
  }
  return out;
}

constexpr Real kInvH = 60;

TEST(LinkLanes, PointTermsEqualTheBlocksLinkByLinkBitForBit) {
  const Links g = random_links(200, 1200);
  const auto ends = g.pool.slot_ends();
  const auto params = g.pool.slot_params();
  ASSERT_GT(g.row[1] - g.row[0], 128u);  // the hub spans runs of lanes
  std::vector<std::uint32_t> points(200);
  for (std::uint32_t i = 0; i < 200; ++i) points[i] = i;
  std::vector<Vec3> f(200, Vec3{1, 2, 3}), f_ref = f;
  std::vector<Mat3> h(200, Mat3::identity()), h_ref = h;
  // Two calls (as two blocks of a sweep) must give what one would.
  maille::add_point_terms(g.pool, {points.data(), 77}, g.row.data(), g.slots.data(), g.x.data(),
                          g.v.data(), kInvH, f.data(), h.data());
  maille::add_point_terms(g.pool, {points.data() + 77, 123}, g.row.data(), g.slots.data(),
                          g.x.data(), g.v.data(), kInvH, f.data(), h.data());
  int stretched = 0, compressed = 0;
  for (const std::uint32_t i : points) {
    Vec3 fi{};
    Mat3 hi;
    for (std::uint32_t k = g.row[i]; k < g.row[i + 1]; ++k) {
      const auto [a, b] = ends[g.slots[k]];
      const LinkBlock blk =
          SpringDamper::block(g.x[a], g.x[b], g.v[a], g.v[b], params[g.slots[k]], kInvH);
      fi += a == i ? blk.force : -blk.force;
      hi += blk.stiffness;
      (norm(g.x[b] - g.x[a]) > params[g.slots[k]].rest_length ? stretched : compressed) += 1;
    }
    f_ref[i] += fi;
    h_ref[i] += hi;
  }
  EXPECT_GT(stretched, 100);
  EXPECT_GT(compressed, 100);
  for (std::uint32_t i = 0; i < 200; ++i) {
    ASSERT_EQ(f[i], f_ref[i]) << "point " << i;
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 3; ++c) ASSERT_EQ(h[i].m[r][c], h_ref[i].m[r][c]) << "point " << i;
  }
}

TEST(LinkLanes, LinkTermsEqualTheBlocksLinkByLinkBitForBit) {
  const Links g = random_links(150, 1000);
  const auto ends = g.pool.slot_ends();
  const auto params = g.pool.slot_params();
  std::vector<Vec3> f(150, Vec3{}), f_ref = f;
  std::vector<Mat3> h(150, Mat3{}), h_ref = h;
  std::vector<Mat3> blocks(ends.size());
  maille::add_link_terms(g.pool, g.x.data(), g.v.data(), kInvH, f.data(), h.data(), blocks.data());
  for (std::size_t l = 0; l < ends.size(); ++l) {
    const auto [a, b] = ends[l];
    const LinkBlock blk = SpringDamper::block(g.x[a], g.x[b], g.v[a], g.v[b], params[l], kInvH);
    f_ref[a] += blk.force;
    f_ref[b] -= blk.force;
    h_ref[a] += blk.stiffness;
    h_ref[b] += blk.stiffness;
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 3; ++c) ASSERT_EQ(blocks[l].m[r][c], blk.stiffness.m[r][c]) << l;
  }
  for (std::uint32_t i = 0; i < 150; ++i) {
    ASSERT_EQ(f[i], f_ref[i]) << "point " << i;
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 3; ++c) ASSERT_EQ(h[i].m[r][c], h_ref[i].m[r][c]) << "point " << i;
  }
}

}  // namespace
}  // namespace maille
