// The pool scheduler (LinkPoolBase::prepare + accumulate: links sorted into bands, cut into
// runs and gathered chunks, bands coloured and split among threads) against the plainest loop:
// for every link, f_a += force, f_b -= force. Every built-in kind, on a random graph and on a
// grid (which makes runs), on 1 and 2 threads. The sums are the same up to summation order.
// Also: the greedy colourings (colour_sets, colour_elements) never put two sets sharing a
// point in one colour, and a conditional kind has a Jacobian for the Euclidean distance only.
#include <gtest/gtest.h>
#include <omp.h>

#include <algorithm>
#include <functional>
#include <random>
#include <vector>

#include "maille/colouring.hpp"
#include "maille/integrator.hpp"
#include "maille/link_loops.hpp"
#include "maille/link_pool.hpp"
#include "maille/links/conditional.hpp"
#include "maille/links/damper.hpp"
#include "maille/links/spring.hpp"
#include "maille/links/spring_damper.hpp"
#include "maille/model.hpp"

namespace maille {
namespace {

struct Graph {
  std::uint32_t points = 0;
  std::vector<LinkEnds> links;
  std::vector<Vec3> x, v;
};

// Random links between random points (no order, no structure: every chunk is a gathered one).
Graph random_graph(std::mt19937_64& rng) {
  Graph g;
  g.points = 700;
  std::uniform_int_distribution<std::uint32_t> pick(0, g.points - 1);
  while (g.links.size() < 4000) {
    const std::uint32_t a = pick(rng), b = pick(rng);
    if (a != b) g.links.push_back({a, b});
  }
  return g;
}

// A 40 x 30 grid with structural, shear and bending links (families that form runs), shuffled.
Graph grid(std::mt19937_64& rng) {
  Graph g;
  const std::uint32_t nx = 40, ny = 30;
  g.points = nx * ny;
  auto id = [&](std::uint32_t i, std::uint32_t j) { return j * nx + i; };
  for (std::uint32_t j = 0; j < ny; ++j)
    for (std::uint32_t i = 0; i < nx; ++i) {
      if (i + 1 < nx) g.links.push_back({id(i, j), id(i + 1, j)});
      if (j + 1 < ny) g.links.push_back({id(i, j), id(i, j + 1)});
      if (i + 1 < nx && j + 1 < ny) g.links.push_back({id(i, j), id(i + 1, j + 1)});
      if (i + 1 < nx && j + 1 < ny) g.links.push_back({id(i + 1, j), id(i, j + 1)});
      if (i + 2 < nx) g.links.push_back({id(i, j), id(i + 2, j)});
    }
  std::shuffle(g.links.begin(), g.links.end(), rng);
  return g;
}

void place(Graph& g, std::mt19937_64& rng, bool on_grid) {
  std::uniform_real_distribution<double> u(-1, 1);
  g.x.resize(g.points);
  g.v.resize(g.points);
  for (std::uint32_t p = 0; p < g.points; ++p) {
    const double gx = on_grid ? 0.05 * (p % 40) : 0, gy = on_grid ? 0.05 * (p / 40) : 0;
    const double jitter = on_grid ? 0.01 : 0.5;
    g.x[p] = {Real(gx + jitter * u(rng)), Real(gy + jitter * u(rng)), Real(jitter * u(rng))};
    g.v[p] = {Real(u(rng)), Real(u(rng)), Real(u(rng))};
  }
}

template <class K>
typename K::Params random_params(std::mt19937_64& rng) {
  std::uniform_real_distribution<double> u(0.5, 2);
  typename K::Params p{};
  for (const auto& field : K::fields) p.*(field.member) = Real(u(rng));
  if constexpr (requires { p.threshold; }) {
    p.threshold = Real(0.08 * u(rng));  // some links active, some not (on both graphs)
    p.rest_length = Real(0.5) * p.threshold;
  } else if constexpr (requires { p.rest_length; }) {
    p.rest_length = Real(0.1 * u(rng));
  }
  return p;
}

template <class K>
void check_kind(Graph g, std::mt19937_64& rng) {
  std::vector<typename K::Params> params;
  for (std::size_t l = 0; l < g.links.size(); ++l) params.push_back(random_params<K>(rng));

  // The plain loop, in the order the links were given; and the scale of each point's sum (the
  // sum of the magnitudes of its terms) to judge the rounding of a reordered sum.
  std::vector<Vec3> naive(g.points);
  std::vector<Real> scale(g.points, 0);
  std::uint64_t active = 0;
  for (std::size_t l = 0; l < g.links.size(); ++l) {
    const auto [a, b] = g.links[l];
    if constexpr (requires { K::is_active(g.x[a], g.x[b], params[l]); }) {
      if (!K::is_active(g.x[a], g.x[b], params[l])) continue;
      ++active;
    }
    const Vec3 fa = K::force(g.x[a], g.x[b], g.v[a], g.v[b], params[l]);
    naive[a] += fa;
    naive[b] -= fa;
    scale[a] += norm(fa);
    scale[b] += norm(fa);
  }

  LinkPool<K> pool;
  for (std::size_t l = 0; l < g.links.size(); ++l) pool.add(g.links[l], params[l]);
  pool.prepare(g.points);
  ASSERT_EQ(pool.size(), g.links.size());

  std::vector<Vec3> by_threads[2];
  for (const int threads : {1, 2}) {
    std::vector<Vec3>& f = by_threads[threads - 1];
    f.assign(g.points, Vec3{});
    LinkCounters counters;
    if (threads == 1) {
      maille::accumulate_forces(pool, g.x.data(), g.v.data(), f.data(), counters);
    } else {
#pragma omp parallel num_threads(2)
      maille::accumulate_forces(pool, g.x.data(), g.v.data(), f.data(), counters);
    }
    if constexpr (requires { K::is_active(g.x[0], g.x[0], params[0]); }) {
      EXPECT_EQ(counters.active, active) << K::keyword << ", " << threads << " threads";
      EXPECT_GT(active, 0u);
      EXPECT_LT(active, g.links.size());
    }
    for (std::uint32_t p = 0; p < g.points; ++p) {
      const Real tol = Real(1e-12) * scale[p] + Real(1e-300);
      ASSERT_NEAR(f[p].x, naive[p].x, tol)
          << K::keyword << ", point " << p << ", " << threads << " threads";
      ASSERT_NEAR(f[p].y, naive[p].y, tol) << K::keyword << ", point " << p;
      ASSERT_NEAR(f[p].z, naive[p].z, tol) << K::keyword << ", point " << p;
    }
  }
  // The pool sums in the same order whatever the thread count.
  EXPECT_EQ(by_threads[0], by_threads[1]) << K::keyword;

  // Its public view of the links is the same set of (ends, params), reordered.
  auto key = [](LinkEnds e, Real p0) { return std::tuple(e.a, e.b, p0); };
  std::vector<std::tuple<std::uint32_t, std::uint32_t, Real>> given, seen;
  for (std::size_t l = 0; l < g.links.size(); ++l)
    given.push_back(key(g.links[l], params[l].*(K::fields[0].member)));
  for (std::size_t l = 0; l < pool.size(); ++l) seen.push_back(key(pool.ends(l), pool.param(l, 0)));
  std::sort(given.begin(), given.end());
  std::sort(seen.begin(), seen.end());
  EXPECT_EQ(given, seen) << K::keyword;
}

template <class K>
void check_kind_on_both_graphs() {
  std::mt19937_64 rng(2024);
  Graph r = random_graph(rng);
  place(r, rng, false);
  check_kind<K>(r, rng);
  Graph gr = grid(rng);
  place(gr, rng, true);
  check_kind<K>(gr, rng);
}

TEST(LinkPools, SpringMatchesThePlainLoop) {
  check_kind_on_both_graphs<Spring>();
}
TEST(LinkPools, DamperMatchesThePlainLoop) {
  check_kind_on_both_graphs<Damper>();
}
TEST(LinkPools, SpringDamperMatchesThePlainLoop) {
  check_kind_on_both_graphs<SpringDamper>();
}
TEST(LinkPools, ConditionalMatchesThePlainLoop) {
  check_kind_on_both_graphs<ConditionalSpringDamper>();
}

// Every set appears once in the order, and no two sets of one colour share a point.
void expect_valid(const Colouring& c, std::size_t sets,
                  const std::function<std::vector<std::uint32_t>(std::uint32_t)>& points_of,
                  std::uint32_t point_count) {
  ASSERT_EQ(c.order.size(), sets);
  ASSERT_GE(c.offsets.size(), 2u);
  EXPECT_EQ(c.offsets.front(), 0u);
  EXPECT_EQ(c.offsets.back(), sets);
  std::vector<std::uint32_t> seen(sets, 0);
  for (const std::uint32_t s : c.order) ++seen.at(s);
  EXPECT_TRUE(std::all_of(seen.begin(), seen.end(), [](std::uint32_t n) { return n == 1; }));
  std::vector<std::int64_t> owner(point_count, -1);  // the set holding the point in this colour
  for (std::size_t colour = 0; colour + 1 < c.offsets.size(); ++colour) {
    std::fill(owner.begin(), owner.end(), -1);
    for (std::uint32_t k = c.offsets[colour]; k < c.offsets[colour + 1]; ++k) {
      const std::uint32_t s = c.order[k];
      for (const std::uint32_t p : points_of(s)) {
        ASSERT_TRUE(owner[p] == -1 || owner[p] == s)
            << "colour " << colour << ": sets " << owner[p] << " and " << s << " share point " << p;
        owner[p] = s;
      }
    }
  }
}

TEST(LinkPools, ColouringsNeverShareAPointWithinAColour) {
  std::mt19937_64 rng(5);
  // Sets: runs of 1 to 40 consecutive links of a random graph (like a pool's bands).
  const Graph g = random_graph(rng);
  std::vector<std::uint32_t> offsets{0}, idx;
  std::uniform_int_distribution<std::size_t> len(1, 40);
  for (std::size_t l = 0; l < g.links.size();) {
    const std::size_t end = std::min(g.links.size(), l + len(rng));
    for (; l < end; ++l) {
      idx.push_back(g.links[l].a);
      idx.push_back(g.links[l].b);
    }
    offsets.push_back(static_cast<std::uint32_t>(idx.size()));
  }
  const Colouring sets = colour_sets(offsets, idx, g.points);
  expect_valid(
      sets, offsets.size() - 1,
      [&](std::uint32_t s) {
        return std::vector<std::uint32_t>(idx.begin() + offsets[s], idx.begin() + offsets[s + 1]);
      },
      g.points);

  // Triangles of a 40 x 30 grid (arity 3), as the wind stage colours its faces.
  std::vector<std::uint32_t> tris;
  for (std::uint32_t j = 0; j + 1 < 30; ++j)
    for (std::uint32_t i = 0; i + 1 < 40; ++i) {
      const std::uint32_t p = j * 40 + i;
      tris.insert(tris.end(), {p, p + 1, p + 41, p, p + 41, p + 40});
    }
  const Colouring faces = colour_elements(tris, 3, 40 * 30);
  expect_valid(
      faces, tris.size() / 3,
      [&](std::uint32_t t) {
        return std::vector<std::uint32_t>{tris[3 * t], tris[3 * t + 1], tris[3 * t + 2]};
      },
      40 * 30);
  EXPECT_LE(faces.offsets.size() - 1, 12u);  // greedy on a grid: a handful of colours
}

// A distance that is not Euclidean (the law acts along it, its Jacobian would differ): the kind
// has no Jacobian, so implicit Euler refuses it by name instead of using the Euclidean blocks.
struct ScaledDistance {
  static constexpr std::string_view keyword = "scaled_conditional";
  static Separation separation(const Vec3& xa, const Vec3& xb) {
    return maille::separation(xa, xb * Real(2));
  }
  static bool within(const Vec3& xa, const Vec3& xb, Real s) {
    return norm2(xb * Real(2) - xa) < s * s;
  }
};

TEST(LinkPools, TheConditionalJacobianExistsForTheEuclideanDistanceOnly) {
  EXPECT_TRUE(LinkPool<ConditionalSpringDamper>{}.has_jacobian());
  EXPECT_FALSE(LinkPool<ConditionalSpringDamperT<ScaledDistance>>{}.has_jacobian());
  Model m;
  m.points.add(PointKind::fixed, 1, {0, 0, 0});
  m.points.add(PointKind::free, 1, {0.1, 0, 0});
  m.links.pool<ConditionalSpringDamperT<ScaledDistance>>().add({0, 1}, {100, 0, 0.5, 0.5});
  const auto scheme = IntegratorRegistry::builtin().find("implicit_euler")->make({});
  EXPECT_NE(scheme->check(m).find("'scaled_conditional' provides no Jacobian"), std::string::npos)
      << scheme->check(m);
}

}  // namespace
}  // namespace maille
