// The helpers written once and used across the engine: compressed rows (detail/csr.hpp), the
// greedy point colouring (colouring.hpp) and a stage's profile columns (profile.hpp). Each is
// tested for what its callers rely on.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <random>
#include <utility>
#include <vector>

#include "maille/colouring.hpp"
#include "maille/detail/csr.hpp"
#include "maille/profile.hpp"

namespace maille {
namespace {

using Edges = std::vector<std::pair<std::uint32_t, std::uint32_t>>;

Edges random_edges(std::uint32_t nodes, std::size_t count, std::uint32_t seed) {
  std::mt19937 rng(seed);
  std::uniform_int_distribution<std::uint32_t> pick(0, nodes - 1);
  Edges e;
  for (std::size_t k = 0; k < count; ++k) e.emplace_back(pick(rng), pick(rng));
  return e;
}

// Every entry lands in its row, in visit order, and the rows cover the values exactly.
TEST(CompressedRows, EachRowHoldsItsEntriesInVisitOrder) {
  const std::uint32_t rows = 50;
  const Edges entries = random_edges(rows, 400, 1);  // (row, value)
  std::vector<std::uint32_t> row, values;
  detail::build_rows(rows, row, values, [&](auto&& emit) {
    for (const auto& [r, v] : entries) emit(r, v);
  });
  ASSERT_EQ(row.size(), rows + 1u);
  EXPECT_EQ(row.front(), 0u);
  EXPECT_EQ(row.back(), entries.size());
  for (std::uint32_t r = 0; r < rows; ++r) {
    std::vector<std::uint32_t> want;
    for (const auto& [er, v] : entries)
      if (er == r) want.push_back(v);
    const std::vector<std::uint32_t> got(values.begin() + row[r], values.begin() + row[r + 1]);
    EXPECT_EQ(got, want) << "row " << r;
  }
}

// Rebuilt at the same size or a little smaller, as a step rebuilds its rows, the arrays keep
// their storage: no allocation in the step (the engine's allocation tests rely on it).
TEST(CompressedRows, RebuildingReusesTheStorage) {
  std::vector<std::uint32_t> row, values;
  const Edges first = random_edges(64, 500, 2), second = random_edges(64, 450, 3);
  auto build = [&](const Edges& e) {
    detail::build_rows(64, row, values, [&](auto&& emit) {
      for (const auto& [r, v] : e) emit(r, v);
    });
  };
  build(first);
  const auto* row_data = row.data();
  const auto* value_data = values.data();
  build(second);
  build(first);
  EXPECT_EQ(row.data(), row_data);
  EXPECT_EQ(values.data(), value_data);
}

// An undirected graph's rows hold each edge at both ends.
TEST(CompressedRows, NeighbourRowsAreSymmetric) {
  const Edges edges = random_edges(30, 120, 4);
  std::vector<std::uint32_t> row, adjacent;
  detail::build_neighbour_rows(30, row, adjacent, [&](auto&& edge) {
    for (const auto& [a, b] : edges) edge(a, b);
  });
  EXPECT_EQ(adjacent.size(), 2 * edges.size());
  for (const auto& [a, b] : edges) {
    const auto in_row = [&](std::uint32_t r, std::uint32_t v) {
      for (std::uint32_t k = row[r]; k < row[r + 1]; ++k)
        if (adjacent[k] == v) return true;
      return false;
    };
    EXPECT_TRUE(in_row(a, b) && in_row(b, a)) << a << "-" << b;
  }
}

// The greedy colouring is a colouring: no two neighbours share a colour; points left out stay
// uncoloured and constrain nothing; greedy uses at most (largest degree + 1) colours.
TEST(PointColouring, NoNeighboursShareAColour) {
  const std::uint32_t n = 200;
  const Edges edges = random_edges(n, 900, 5);
  std::vector<std::uint32_t> row, adjacent;
  detail::build_neighbour_rows(n, row, adjacent, [&](auto&& edge) {
    for (const auto& [a, b] : edges)
      if (a != b) edge(a, b);
  });
  std::vector<std::uint32_t> points;
  for (std::uint32_t i = 0; i < n; ++i)
    if (i % 7 != 0) points.push_back(i);  // every seventh point fixed
  std::vector<std::uint32_t> colour(n, kUncoloured), stamp;
  const std::uint32_t colours =
      colour_points(points, colour, stamp, [&](std::uint32_t i, auto&& visit) {
        for (std::uint32_t k = row[i]; k < row[i + 1]; ++k) visit(adjacent[k]);
      });
  std::uint32_t degree = 0;
  for (std::uint32_t i = 0; i < n; ++i) {
    degree = std::max(degree, row[i + 1] - row[i]);
    if (i % 7 == 0) {
      EXPECT_EQ(colour[i], kUncoloured) << i;
      continue;
    }
    ASSERT_LT(colour[i], colours) << i;
    for (std::uint32_t k = row[i]; k < row[i + 1]; ++k) {
      if (adjacent[k] % 7 == 0) continue;
      EXPECT_NE(colour[i], colour[adjacent[k]]) << i << "-" << adjacent[k];
    }
  }
  EXPECT_LE(colours, degree + 1);
  // The same call again (stale stamps in `stamp`) gives the same colours.
  std::vector<std::uint32_t> again(n, kUncoloured);
  colour_points(points, again, stamp, [&](std::uint32_t i, auto&& visit) {
    for (std::uint32_t k = row[i]; k < row[i + 1]; ++k) visit(adjacent[k]);
  });
  EXPECT_EQ(again, colour);
}

// A stage's columns register at its first write, in their declared order (stats.csv's order),
// counters and gauges apart; later writes reuse them.
TEST(ProfileColumnsTest, RegisterInOrderAtTheFirstWrite) {
  Profile p;
  ProfileColumns c{{"a_count"}, {"a_gauge", true}, {"b_count"}};
  EXPECT_TRUE(p.counters().empty());
  c.gauge(p, 1, 2.5);
  ASSERT_EQ(p.counters().size(), 2u);
  ASSERT_EQ(p.gauges().size(), 1u);
  EXPECT_EQ(p.counters()[0].name, "a_count");
  EXPECT_EQ(p.counters()[1].name, "b_count");
  EXPECT_EQ(p.gauges()[0].last, 2.5);
  c.count(p, 2, 7);
  c.add(p, 2, 3);
  EXPECT_EQ(p.counters()[1].last, 10u);
  EXPECT_EQ(p.counters().size(), 2u);
}

// set() writes every column in order, each as declared: a count (any whole type) or a gauge.
TEST(ProfileColumnsTest, SetWritesEveryColumnAsDeclared) {
  Profile p;
  ProfileColumns c{{"a_count"}, {"a_gauge", true}, {"b_count"}};
  c.set(p, {std::uint64_t{4}, 0.25f, 9u});
  ASSERT_EQ(p.counters().size(), 2u);
  ASSERT_EQ(p.gauges().size(), 1u);
  EXPECT_EQ(p.counters()[0].last, 4u);
  EXPECT_EQ(p.gauges()[0].last, 0.25);
  EXPECT_EQ(p.counters()[1].last, 9u);
}

}  // namespace
}  // namespace maille
