#include "exclusion.hpp"

#include <algorithm>
#include <cstdlib>

#include "maille/detail/csr.hpp"

namespace maille::collision {

void CellSignature::add(std::int32_t g, std::int32_t i, std::int32_t j) {
  if (group == -2) {
    *this = {g, i, i, j, j};
    return;
  }
  if (group != g || g < 0) {
    group = -1;
    return;
  }
  i0 = std::min(i0, i), i1 = std::max(i1, i), j0 = std::min(j0, j), j1 = std::max(j1, j);
}

void CellSignature::merge(const CellSignature& o) {
  if (o.group == -2) return;
  if (group == -2) {
    *this = o;
    return;
  }
  if (group != o.group || group < 0) {
    group = -1;
    return;
  }
  i0 = std::min(i0, o.i0), i1 = std::max(i1, o.i1), j0 = std::min(j0, o.j0),
  j1 = std::max(j1, o.j1);
}

namespace {

// Point adjacency through every always-active link (CSR over all points).
struct Adjacency {
  std::vector<std::uint32_t> offsets, to;
};

Adjacency adjacency(const Model& m) {
  Adjacency a;
  detail::build_neighbour_rows(m.points.size(), a.offsets, a.to, [&](auto&& edge) {
    for (const auto& pool : m.links.pools())
      if (!pool->conditional())
        for (const LinkEnds& e : pool->slot_ends()) edge(e.a, e.b);
  });
  return a;
}

// Breadth-first search to depth R; calls reached(point) for every point at distance 1..R.
class BoundedBfs {
 public:
  explicit BoundedBfs(const Adjacency& a) : a_(a), stamp_(a.offsets.size() - 1, 0) {}
  template <class F>
  void run(std::uint32_t from, int depth, F&& reached) {
    ++epoch_;
    stamp_[from] = epoch_;
    frontier_.assign(1, from);
    for (int d = 0; d < depth && !frontier_.empty(); ++d) {
      next_.clear();
      for (std::uint32_t p : frontier_)
        for (std::uint32_t k = a_.offsets[p]; k < a_.offsets[p + 1]; ++k) {
          const std::uint32_t q = a_.to[k];
          if (stamp_[q] == epoch_) continue;
          stamp_[q] = epoch_;
          next_.push_back(q);
          reached(q);
        }
      frontier_.swap(next_);
    }
  }

 private:
  const Adjacency& a_;
  std::vector<std::uint32_t> stamp_, frontier_, next_;
  std::uint32_t epoch_ = 0;
};

}  // namespace

TopologicalExclusion::TopologicalExclusion(const Model& m, const std::vector<std::uint32_t>& set,
                                           int radius, bool signature)
    : radius_(radius), signature_(signature), grid_of_(set.size()) {
  offsets_.assign(set.size() + 1, 0);
  if (radius_ == 0) return;
  const Adjacency adj = adjacency(m);
  BoundedBfs bfs(adj);
  std::vector<std::int32_t> local(m.points.size(), -1);
  for (std::size_t k = 0; k < set.size(); ++k) local[set[k]] = std::int32_t(k);

  if (signature_) {
    for (const Group& g : m.groups) {
      if (g.grid_nx < 2 || g.grid_ny < 2) continue;
      const auto nx = std::int32_t(g.grid_nx), ny = std::int32_t(g.grid_ny);
      auto ij = [&](std::uint32_t p) {
        const auto r = std::int32_t(p - g.first);
        return std::pair{r % nx, r / nx};
      };
      auto inside = [&](std::uint32_t p) { return p >= g.first && p < g.first + g.count; };
      // The stencil at the centre: every offset reached within R.
      Stencil st;
      const std::uint32_t centre = g.first + std::uint32_t((ny / 2) * nx + nx / 2);
      std::vector<std::pair<std::int32_t, std::int32_t>> offs;
      // Plain variables, not structured bindings: clang 14 (the fuzz build) cannot capture those.
      const std::int32_t ci = ij(centre).first, cj = ij(centre).second;
      bfs.run(centre, radius_, [&](std::uint32_t q) {
        if (!inside(q)) return;
        const auto [qi, qj] = ij(q);
        offs.push_back({qi - ci, qj - cj});
        st.reach = std::max({st.reach, std::abs(qi - ci), std::abs(qj - cj)});
      });
      const std::int32_t w = 2 * st.reach + 1;
      st.bits.assign(std::size_t(w * w), 0);
      for (auto [di, dj] : offs) st.bits[std::size_t((dj + st.reach) * w + di + st.reach)] = 1;
      auto in = [&](std::int32_t di, std::int32_t dj) {
        return std::abs(di) <= st.reach && std::abs(dj) <= st.reach &&
               st.bits[std::size_t((dj + st.reach) * w + di + st.reach)] != 0;
      };
      // The grid must be translation-invariant: the stencil, clipped to the grid, must give
      // what a search finds at the corners and the edges' middles. Otherwise: matrix rows.
      bool regular = true;
      for (const auto& probe_ij :
           std::vector<std::pair<std::int32_t, std::int32_t>>{{0, 0},
                                                              {nx - 1, 0},
                                                              {0, ny - 1},
                                                              {nx - 1, ny - 1},
                                                              {nx / 2, 0},
                                                              {0, ny / 2},
                                                              {nx - 1, ny / 2},
                                                              {nx / 2, ny - 1},
                                                              {1, 1}}) {
        const std::int32_t pi = probe_ij.first, pj = probe_ij.second;
        const std::uint32_t probe = g.first + std::uint32_t(pj * nx + pi);
        std::size_t found = 0;
        bfs.run(probe, radius_, [&](std::uint32_t q) {
          if (!inside(q)) return;
          const auto [qi, qj] = ij(q);
          regular &= in(qi - pi, qj - pj);
          ++found;
        });
        std::size_t expected = 0;
        for (auto [di, dj] : offs)
          expected += pi + di >= 0 && pi + di < nx && pj + dj >= 0 && pj + dj < ny;
        regular &= found == expected;
      }
      if (!regular) continue;
      std::int32_t span = 0;
      while (span < st.reach) {
        bool full = true;
        for (std::int32_t dj = -(span + 1); dj <= span + 1 && full; ++dj)
          for (std::int32_t di = -(span + 1); di <= span + 1 && full; ++di)
            full = (di == 0 && dj == 0) || in(di, dj);
        if (!full) break;
        ++span;
      }
      const auto id = std::int32_t(stencils_.size());
      stencils_.push_back(std::move(st));
      full_span_.push_back(span);
      for (std::uint32_t p = g.first; p < g.first + g.count; ++p)
        if (local[p] >= 0) {
          const auto [pi, pj] = ij(p);
          grid_of_[std::size_t(local[p])] = {id, pi, pj};
        }
    }
  }
  // Matrix rows: every neighbour within R, except, for a particle the stencils cover, those of
  // its own grid group (the stencil answers for them; rows stay empty on plain cloth). Without
  // stencils, the rows' room is reserved from the sampled bound: grown by doubling, the array
  // could hold up to twice its entries, three times while it moved. (The 1.28 GB measured for
  // an estimate of 285 MB at R = 16 on 256^2 had three causes: rows twice the (2R + 1)^2 the
  // estimate assumed, two engines alive at once when the stage was reset, and this growth.)
  if (!signature_) neighbours_.reserve(sampled_row_bound(m, set, radius_) * set.size());
  std::vector<std::uint32_t> row;
  for (std::size_t k = 0; k < set.size(); ++k) {
    row.clear();
    const std::int32_t own = grid_of_[k].group;
    bfs.run(set[k], radius_, [&](std::uint32_t q) {
      const std::int32_t lq = local[q];
      if (lq < 0) return;
      if (own >= 0 && grid_of_[std::size_t(lq)].group == own) return;
      row.push_back(std::uint32_t(lq));
    });
    std::sort(row.begin(), row.end());
    neighbours_.insert(neighbours_.end(), row.begin(), row.end());
    offsets_[k + 1] = std::uint32_t(neighbours_.size());
  }
}

bool TopologicalExclusion::matrix_excluded(std::uint32_t a, std::uint32_t b) const {
  if (radius_ == 0) return false;
  const auto* begin = neighbours_.data() + offsets_[a];
  const auto* end = neighbours_.data() + offsets_[a + 1];
  for (const auto* p = begin; p < end; ++p)  // short rows: a linear scan beats bisection
    if (*p >= b) return *p == b;
  return false;
}

std::uint64_t TopologicalExclusion::sampled_row_bound(const Model& m,
                                                      const std::vector<std::uint32_t>& set,
                                                      int radius) {
  if (radius == 0 || set.empty()) return 0;
  const Adjacency adj = adjacency(m);
  BoundedBfs bfs(adj);
  std::vector<std::uint8_t> in(m.points.size(), 0);
  for (const std::uint32_t p : set) in[p] = 1;
  std::uint64_t longest = 0;
  auto sample = [&](std::uint32_t p) {
    std::uint64_t row = 0;
    bfs.run(p, radius, [&](std::uint32_t q) { row += in[q]; });
    longest = std::max(longest, row);
  };
  // The middle of each grid group (the longest rows of a cloth), then 64 particles spread by
  // multiplicative hashing: evenly spaced indices would all fall in one column of a grid whose
  // width divides their spacing (a 256-wide cloth's left edge: half rows).
  for (const Group& g : m.groups)
    if (g.grid_nx >= 2 && g.grid_ny >= 2) {
      const std::uint32_t centre = g.first + (g.grid_ny / 2) * g.grid_nx + g.grid_nx / 2;
      if (in[centre]) sample(centre);
    }
  constexpr std::uint64_t kSamples = 64;
  for (std::uint64_t k = 0; k < kSamples && k < set.size(); ++k)
    sample(set[std::size_t((k * 0x9E3779B97F4A7C15ull >> 11) % set.size())]);
  return longest;
}

std::size_t TopologicalExclusion::bytes() const {
  std::size_t n = offsets_.size() * 4 + neighbours_.size() * 4 + grid_of_.size() * sizeof(Grid);
  for (const auto& s : stencils_) n += s.bits.size();
  return n;
}

}  // namespace maille::collision
