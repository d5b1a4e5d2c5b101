// The crossing-pair count behind stats.csv's `intersecting_pairs` (maille/intersections.hpp):
// exact on constructed configurations (a crossing counts 1; touching, sharing and coplanar
// overlap count 0), and the same count as an independent brute-force test (tests/
// intersections.hpp: Moller-Trumbore on every pair of boxes) on random triangle soups.
#include <gtest/gtest.h>

#include <random>
#include <vector>

#include "intersections.hpp"
#include "maille/intersections.hpp"

namespace {

using maille::IntersectionCount;
using maille::Triangle;
using maille::Vec3;

std::size_t count(const std::vector<Vec3>& x, const std::vector<Triangle>& t) {
  IntersectionCount c;
  return c.count(x, t);
}

// Triangle 0 in the plane z = 0; triangle 1 vertical, its corners 3, 4, 5 placed by the test.
std::vector<Vec3> pair_with(Vec3 p, Vec3 q, Vec3 r) {
  return {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, p, q, r};
}
const std::vector<Triangle> kPair{{0, 1, 2}, {3, 4, 5}};

TEST(Intersections, ACrossingPairCountsOnce) {
  // A vertical triangle through the middle of the horizontal one.
  EXPECT_EQ(count(pair_with({0.2, 0.2, -0.5}, {0.2, 0.2, 0.5}, {0.6, 0.6, 0.5}), kPair), 1u);
  // Two triangles that cross each other's edges (a chain link): still one pair.
  EXPECT_EQ(count(pair_with({0.3, -0.5, 0.2}, {0.3, 0.5, 0.2}, {0.3, 0.2, -0.8}), kPair), 1u);
}

TEST(Intersections, TouchingIsNotCrossing) {
  // A corner resting on the face, an edge lying on the face, a triangle above it.
  EXPECT_EQ(count(pair_with({0.2, 0.2, 0}, {0.2, 0.2, 1}, {0.6, 0.2, 1}), kPair), 0u);
  EXPECT_EQ(count(pair_with({0.1, 0.1, 0}, {0.4, 0.1, 0}, {0.2, 0.2, 1}), kPair), 0u);
  EXPECT_EQ(count(pair_with({0.2, 0.2, 1e-9}, {0.4, 0.2, 1}, {0.2, 0.4, 1}), kPair), 0u);
  // Coplanar and overlapping: no transversal crossing.
  EXPECT_EQ(count(pair_with({0.1, 0.1, 0}, {2, 0.1, 0}, {0.1, 2, 0}), kPair), 0u);
  // Far apart.
  EXPECT_EQ(count(pair_with({5, 5, 5}, {6, 5, 5}, {5, 6, 5}), kPair), 0u);
}

TEST(Intersections, PairsSharingACornerAreLeftOut) {
  // Neighbours of a folded cloth share an edge or a corner: never counted.
  std::vector<Vec3> x{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0.2, 0.2, -0.5}, {0.6, 0.6, 0.5}};
  EXPECT_EQ(count(x, {{0, 1, 2}, {0, 3, 4}}), 0u);  // would cross, but shares corner 0
  EXPECT_EQ(count(x, {{0, 1, 2}, {1, 2, 3}}), 0u);  // a shared edge
}

TEST(Intersections, AgreesWithABruteForceCount) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(0, 1), small(-0.15, 0.15);
  for (int trial = 0; trial < 20; ++trial) {
    std::vector<Vec3> x;
    std::vector<Triangle> t;
    for (std::uint32_t k = 0; k < 300; ++k) {
      const Vec3 c{u(rng), u(rng), u(rng)};
      for (int j = 0; j < 3; ++j) x.push_back(c + Vec3{small(rng), small(rng), small(rng)});
      t.push_back({3 * k, 3 * k + 1, 3 * k + 2});
    }
    const std::size_t brute = maille::test::count_self_intersections(x, t);
    EXPECT_EQ(count(x, t), brute) << "trial " << trial;
    EXPECT_GT(brute, 0u);
  }
}

}  // namespace
