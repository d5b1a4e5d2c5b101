// The coarse correction of vertex block descent (vbd_coarse.hpp has the method).
#include "vbd_coarse.hpp"

#include <Eigen/OrderingMethods>
#include <Eigen/SparseCholesky>
#include <Eigen/SparseCore>
#include <algorithm>
#include <array>
#include <limits>
#include <utility>

#include "implicit_system.hpp"
#include "maille/detail/csr.hpp"
#include "maille/link_set.hpp"

namespace maille {

namespace {

using Sparse = Eigen::SparseMatrix<double, Eigen::ColMajor, int>;

// Eigen's LDL^T on a matrix that is already in its fill-reducing order (upper triangle): the
// public factorize() builds a temporary matrix per call, which would allocate in every step.
class PreorderedLdlt
    : public Eigen::SimplicialLDLT<Sparse, Eigen::Upper, Eigen::NaturalOrdering<int>> {
 public:
  void analyse(const Sparse& upper) { analyzePattern_preordered(upper, true); }
  void factor(const Sparse& upper) { factorize_preordered<true>(upper); }
};

constexpr std::uint32_t kNone = std::numeric_limits<std::uint32_t>::max();
// A link's place in the coarse matrix: an off-diagonal block (>= 0), inside aggregate A
// (-1 - A), or nowhere (a fixed end: its block is in the free end's diagonal already).
constexpr std::int64_t kNowhere = std::numeric_limits<std::int64_t>::min();
// The prolongation's smoothing weight: 4 / (3 rho), rho <= 2 the spectral radius of D^-1 H for
// a Hessian whose diagonal blocks hold every link's block (smoothed aggregation's usual choice).
constexpr Real kSmoothing = Real(2) / Real(3);
// The coarse level's size: aggregates are aggregated again until there are at most this many.
// The LDL^T's cost grows about as their number to the power 1.5 on a cloth, and was 37 % of the
// step with 1849 aggregates (a 128^2 cloth); larger aggregates converge less per correction.
// Cloth on a sphere at 1/60 s, 10 sweeps, largest stretch (at most 300 / 600 / 2000): 64^2
// 7.4 / 5.6 / 5.6 %, 128^2 9.1 / 9.1 / 7.4 % (before the final contact rules: docs/implicit.md).
constexpr std::size_t kMaxAggregates = 600;
// Jacobi smoothings of the prolongation: each spreads a jump between aggregates over one more
// ring of points. The same runs with 1 and 2: 64^2 4.4 and 5.6 %, 128^2 15.7 and 9.1 %.
constexpr int kSmoothingSteps = 2;
// The largest step along the direction: the model's alpha was 1.3 to 3.1 on the cloth on a
// sphere (the smoothed direction is still too stiff for a smooth error, vbd_coarse.hpp); a much
// larger one means the quadratic model is poor.
constexpr Real kMaxStep = 16;

}  // namespace

struct CoarseCorrection::Impl {
  struct Pool {
    const LinkPoolBase* pool = nullptr;
    std::vector<Mat3> blocks;          // [links] J_x + J_v / h at the correction (blocks_of)
    std::vector<std::int64_t> target;  // [links] see kNowhere
  };
  std::vector<Pool> pools;
  std::vector<std::uint32_t> free;           // free points, increasing
  std::vector<std::uint32_t> aggregate;      // [points] kNone for fixed points
  std::size_t count = 0;                     // aggregates
  std::vector<std::uint32_t> order;          // [aggregates] place in the factorised order
  std::vector<Mat3> values;                  // [aggregates + off-diagonal blocks]
  std::vector<std::array<int, 9>> value_at;  // into upper's values, -1: lower triangle
  Sparse upper;
  PreorderedLdlt ldlt;
  bool ready = false;  // prepared this step
  Eigen::VectorXd rhs, solution;
  std::vector<Vec3> p0, hp;              // [points]
  std::vector<Mat3> diag, diag_inverse;  // [points] H's diagonal blocks when prepared

  void aggregate_points(std::span<const std::uint32_t> free_points, std::size_t points);
  void pattern();
  void multiply(const Mat3* diag, const Vec3* u, Vec3* out) const;
};

CoarseCorrection::CoarseCorrection() = default;
CoarseCorrection::~CoarseCorrection() = default;
CoarseCorrection::CoarseCorrection(CoarseCorrection&&) noexcept = default;
CoarseCorrection& CoarseCorrection::operator=(CoarseCorrection&&) noexcept = default;

void CoarseCorrection::reset() {
  impl_.reset();
}
std::size_t CoarseCorrection::aggregates() const {
  return impl_ ? impl_->count : 0;
}
namespace {

// Vanek's greedy aggregation of `nodes` (in order) over a graph given by rows: a node whose
// neighbours are all unassigned starts an aggregate with them; the nodes left join the aggregate
// of their first assigned neighbour; nodes with no neighbour are aggregates of their own.
// assign[node] is kNone on entry for every node of `nodes`. Returns the number of aggregates.
std::uint32_t greedy_aggregates(std::span<const std::uint32_t> nodes,
                                const std::vector<std::uint32_t>& row,
                                const std::vector<std::uint32_t>& adjacent,
                                std::vector<std::uint32_t>& assign) {
  std::uint32_t count = 0;
  for (const std::uint32_t i : nodes) {
    if (assign[i] != kNone) continue;
    bool alone = true;
    for (std::uint32_t k = row[i]; k < row[i + 1] && alone; ++k)
      alone = assign[adjacent[k]] == kNone;
    if (!alone) continue;
    assign[i] = count;
    for (std::uint32_t k = row[i]; k < row[i + 1]; ++k) assign[adjacent[k]] = count;
    ++count;
  }
  for (const std::uint32_t i : nodes) {
    if (assign[i] != kNone) continue;
    for (std::uint32_t k = row[i]; k < row[i + 1]; ++k)
      if (assign[adjacent[k]] != kNone) {
        assign[i] = assign[adjacent[k]];
        break;
      }
    if (assign[i] == kNone) assign[i] = count++;
  }
  return count;
}

// Rows of the undirected graph of `edges` over n nodes (self-edges dropped).
void graph_rows(std::size_t n, const std::vector<std::pair<std::uint32_t, std::uint32_t>>& edges,
                std::vector<std::uint32_t>& row, std::vector<std::uint32_t>& adjacent) {
  detail::build_neighbour_rows(n, row, adjacent, [&](auto&& edge) {
    for (const auto& [a, b] : edges)
      if (a != b) edge(a, b);
  });
}

}  // namespace

// Aggregates of the free points: greedy aggregation over the links, then of the aggregates
// over the links between them (kPasses in all).
void CoarseCorrection::Impl::aggregate_points(std::span<const std::uint32_t> free_points,
                                              std::size_t points) {
  free.assign(free_points.begin(), free_points.end());
  aggregate.assign(points, kNone);
  std::vector<std::uint8_t> is_free(points, 0);
  for (const std::uint32_t i : free) is_free[i] = 1;
  std::vector<std::pair<std::uint32_t, std::uint32_t>> edges;
  for (const Pool& p : pools)
    for (const LinkEnds& e : p.pool->slot_ends())
      if (is_free[e.a] && is_free[e.b]) edges.emplace_back(e.a, e.b);
  std::vector<std::uint32_t> row, adjacent, assign(points, kNone), nodes;
  graph_rows(points, edges, row, adjacent);
  count = greedy_aggregates(free, row, adjacent, assign);
  for (const std::uint32_t i : free) aggregate[i] = assign[i];
  std::vector<std::pair<std::uint32_t, std::uint32_t>> coarse_edges;
  while (count > kMaxAggregates) {
    coarse_edges.clear();
    for (const auto& [a, b] : edges) coarse_edges.emplace_back(aggregate[a], aggregate[b]);
    graph_rows(count, coarse_edges, row, adjacent);
    nodes.resize(count);
    for (std::uint32_t a = 0; a < count; ++a) nodes[a] = a;
    assign.assign(count, kNone);
    count = greedy_aggregates(nodes, row, adjacent, assign);
    for (const std::uint32_t i : free) aggregate[i] = assign[aggregate[i]];
  }
}

// The coarse matrix's blocks (aggregates, then one per pair of linked aggregates), each link's
// block, the fill-reducing order and the factorisation's symbolic part.
void CoarseCorrection::Impl::pattern() {
  std::vector<std::pair<std::uint32_t, std::uint32_t>> pairs;
  for (const Pool& p : pools)
    for (const LinkEnds& e : p.pool->slot_ends()) {
      const std::uint32_t a = aggregate[e.a], b = aggregate[e.b];
      if (a != kNone && b != kNone && a != b) pairs.emplace_back(std::min(a, b), std::max(a, b));
    }
  std::sort(pairs.begin(), pairs.end());
  pairs.erase(std::unique(pairs.begin(), pairs.end()), pairs.end());
  for (Pool& p : pools) {
    const auto ends = p.pool->slot_ends();
    p.blocks.assign(ends.size(), Mat3{});
    p.target.assign(ends.size(), kNowhere);
    for (std::size_t l = 0; l < ends.size(); ++l) {
      const std::uint32_t a = aggregate[ends[l].a], b = aggregate[ends[l].b];
      if (a == kNone || b == kNone) continue;
      if (a == b) {
        p.target[l] = -1 - std::int64_t(a);
        continue;
      }
      const auto at = std::lower_bound(pairs.begin(), pairs.end(),
                                       std::make_pair(std::min(a, b), std::max(a, b)));
      p.target[l] = std::int64_t(count) + (at - pairs.begin());
    }
  }
  // Fill-reducing order of the aggregates' graph (approximate minimum degree).
  Sparse graph(static_cast<Eigen::Index>(count), static_cast<Eigen::Index>(count));
  std::vector<Eigen::Triplet<double, int>> t;
  for (std::size_t a = 0; a < count; ++a) t.emplace_back(int(a), int(a), 1.0);
  for (const auto& [a, b] : pairs) {
    t.emplace_back(int(a), int(b), 1.0);
    t.emplace_back(int(b), int(a), 1.0);
  }
  graph.setFromTriplets(t.begin(), t.end());
  Eigen::PermutationMatrix<Eigen::Dynamic, Eigen::Dynamic, int> inverse;
  Eigen::AMDOrdering<int>()(graph, inverse);
  const Eigen::PermutationMatrix<Eigen::Dynamic, Eigen::Dynamic, int> forward = inverse.inverse();
  order.resize(count);
  for (std::size_t a = 0; a < count; ++a)
    order[a] = std::uint32_t(forward.indices()[Eigen::Index(a)]);
  // The scalar matrix, upper triangle, in that order.
  std::vector<std::pair<std::uint32_t, std::uint32_t>> blocks;
  for (std::size_t a = 0; a < count; ++a) blocks.emplace_back(std::uint32_t(a), std::uint32_t(a));
  blocks.insert(blocks.end(), pairs.begin(), pairs.end());
  t.clear();
  auto place = [&](std::uint32_t a, std::uint32_t b, int i, int j) {
    const int r = 3 * int(order[a]) + i, c = 3 * int(order[b]) + j;
    return std::make_pair(std::min(r, c), std::max(r, c));
  };
  for (const auto& [a, b] : blocks)
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) {
        if (a == b && j < i) continue;
        const auto [r, c] = place(a, b, i, j);
        t.emplace_back(r, c, 0.0);
      }
  const auto n = Eigen::Index(3 * count);
  upper.resize(n, n);
  upper.setFromTriplets(t.begin(), t.end());
  upper.makeCompressed();
  value_at.assign(blocks.size(), {});
  for (std::size_t k = 0; k < blocks.size(); ++k) {
    const auto [a, b] = blocks[k];
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) {
        int& at = value_at[k][std::size_t(3 * i + j)];
        at = -1;
        if (a == b && j < i) continue;
        const auto [r, c] = place(a, b, i, j);
        const int* begin = upper.innerIndexPtr() + upper.outerIndexPtr()[c];
        const int* end = upper.innerIndexPtr() + upper.outerIndexPtr()[c + 1];
        at = int(std::lower_bound(begin, end, r) - upper.innerIndexPtr());
      }
  }
  values.assign(blocks.size(), Mat3{});
  ldlt.analyse(upper);
  rhs.setZero(n);
  solution.setZero(n);
}

void CoarseCorrection::build(const Model& m, std::span<const std::uint32_t> free,
                             std::size_t points) {
  impl_ = std::make_unique<Impl>();
  Impl& c = *impl_;
  for (const auto& pool : m.links.pools())
    if (!pool->conditional() && pool->has_jacobian() && pool->size() > 0)
      c.pools.push_back({pool.get(), {}, {}});
  c.aggregate_points(free, points);
  c.pattern();
  c.p0.assign(points, Vec3{});
  c.hp.assign(points, Vec3{});
  c.diag.assign(points, Mat3{});
  c.diag_inverse.assign(points, Mat3{});
}

Mat3* CoarseCorrection::blocks_of(const LinkPoolBase* pool) {
  if (!impl_) return nullptr;
  for (Impl::Pool& p : impl_->pools)
    if (p.pool == pool) return p.blocks.data();
  return nullptr;
}

bool CoarseCorrection::prepare(const Mat3* diag) {
  if (!impl_ || impl_->count == 0) return false;
  Impl& c = *impl_;
  std::fill(c.values.begin(), c.values.end(), Mat3{});
  for (const std::uint32_t i : c.free) {
    c.values[c.aggregate[i]] += diag[i];
    c.diag[i] = diag[i];
    c.diag_inverse[i] = inverse_spd(diag[i]);
  }
  for (Impl::Pool& p : c.pools) {
    for (std::size_t l = 0; l < p.blocks.size(); ++l) {
      const std::int64_t t = p.target[l];
      if (t == kNowhere) continue;
      const Mat3& k = p.blocks[l];
      if (t >= 0)
        c.values[std::size_t(t)] += k * Real(-1);
      else
        c.values[std::size_t(-1 - t)] += k * Real(-2);
    }
  }
  double* out = c.upper.valuePtr();
  for (std::size_t k = 0; k < c.values.size(); ++k)
    for (std::size_t e = 0; e < 9; ++e)
      if (c.value_at[k][e] >= 0) out[c.value_at[k][e]] = double(c.values[k].m[e / 3][e % 3]);
  return factorise();
}

CoarseCorrection::Matrix CoarseCorrection::matrix() const {
  if (!impl_ || impl_->count == 0) return {};
  const Sparse& u = impl_->upper;
  return {int(u.rows()), u.outerIndexPtr(), u.innerIndexPtr(), u.valuePtr()};
}

bool CoarseCorrection::factorise() {
  if (!impl_ || impl_->count == 0) return false;
  Impl& c = *impl_;
  c.ldlt.factor(c.upper);
  c.ready = c.ldlt.info() == Eigen::Success && c.ldlt.vectorD().minCoeff() > 0;
  return c.ready;
}

// out = H u with H's diagonal blocks `diag` and the kept links' off-diagonal blocks -K_l.
void CoarseCorrection::Impl::multiply(const Mat3* d, const Vec3* u, Vec3* out) const {
  for (const std::uint32_t i : free) out[i] = d[i] * u[i];
  for (const Pool& p : pools) {
    const auto ends = p.pool->slot_ends();
    for (std::size_t l = 0; l < ends.size(); ++l) {
      if (p.target[l] == kNowhere) continue;
      const Mat3& b = p.blocks[l];
      const auto [a, c] = ends[l];
      out[a] -= b * u[c];
      out[c] -= b * u[a];
    }
  }
}

Real CoarseCorrection::direction(const Vec3* g, Vec3* p) {
  if (!impl_ || !impl_->ready) return 0;
  Impl& c = *impl_;
  c.rhs.setZero();
  for (const std::uint32_t i : c.free) {
    const Eigen::Index at = 3 * Eigen::Index(c.order[c.aggregate[i]]);
    c.rhs[at] += double(g[i].x);
    c.rhs[at + 1] += double(g[i].y);
    c.rhs[at + 2] += double(g[i].z);
  }
  c.solution = c.ldlt.solve(c.rhs);
  for (const std::uint32_t i : c.free) {
    const Eigen::Index at = 3 * Eigen::Index(c.order[c.aggregate[i]]);
    c.p0[i] = Vec3{Real(c.solution[at]), Real(c.solution[at + 1]), Real(c.solution[at + 2])};
  }
  // Smoothed once: p = p0 - w D^-1 H p0.
  for (const std::uint32_t i : c.free) p[i] = c.p0[i];
  for (int k = 0; k < kSmoothingSteps; ++k) {
    c.multiply(c.diag.data(), p, c.hp.data());
    for (const std::uint32_t i : c.free) p[i] = p[i] - (c.diag_inverse[i] * c.hp[i]) * kSmoothing;
  }
  c.multiply(c.diag.data(), p, c.hp.data());
  Real slope = 0, curvature = 0;
  for (const std::uint32_t i : c.free) {
    slope += dot(g[i], p[i]);
    curvature += dot(p[i], c.hp[i]);
  }
  if (!(slope > 0 && curvature > 0)) return 0;
  return std::min(slope / curvature, kMaxStep);
}

}  // namespace maille
