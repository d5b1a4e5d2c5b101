// Assembled alternative for implicit Euler: the same matrix in an Eigen sparse matrix of fixed
// pattern (3x3 blocks for every point and every linked pair), values refilled each step from
// the link blocks, solved by Eigen's ConjugateGradient with a diagonal preconditioner. Kept to
// measure against the matrix-free solver (docs/benchmarks.md) and to cross-check it in tests;
// Eigen's CG allocates its work vectors on every solve.
#include <Eigen/IterativeLinearSolvers>
#include <Eigen/Sparse>
#include <algorithm>
#include <array>
#include <cstdint>
#include <vector>

#include "implicit_system.hpp"
#include "maille/link_loops.hpp"

namespace maille {

namespace {

using Sparse = Eigen::SparseMatrix<Real, Eigen::RowMajor, std::int64_t>;
using Vector = Eigen::Matrix<Real, Eigen::Dynamic, 1>;

class EigenSystem final : public ImplicitSystem {
 public:
  EigenSystem(const Model& m, int threads) : model_(m) {
    Eigen::setNbThreads(threads);
    const std::size_t n = m.points.size();
    free_.resize(n);
    for (std::size_t i = 0; i < n; ++i) free_[i] = m.points.inv_mass[i] > 0;
    build_pattern();
    for (const auto& pool : m.links.pools()) blocks_.emplace_back(pool->size());
  }

  // Transient links (stages' contacts) change the sparsity pattern every step: this solver
  // leaves them explicit (the matrix-free solver takes them), and point contacts too.
  void linearise(const Model& m, const State& s, Real h, Vec3* rhs,
                 std::span<const LinkPoolBase* const>, std::span<PointContacts* const>,
                 std::span<TriangleContacts* const>) override {
    const auto pools = m.links.pools();
    for (std::size_t p = 0; p < pools.size(); ++p)
      implicit_blocks(*pools[p], s.x().data(), s.v().data(), h, blocks_[p].data(), rhs);
    Real* val = matrix_.valuePtr();
    std::fill(val, val + matrix_.nonZeros(), Real(0));
    const Real drag = h * m.fields.air_drag;
    for (std::uint32_t i = 0; i < m.points.size(); ++i)
      add_block(i, i, Mat3::identity() * (m.points.mass[i] * (1 + drag)));
    // Row a: (m + C) u_a - C u_b; row b: -C u_a + (m + C) u_b.
    for (std::size_t p = 0; p < pools.size(); ++p)
      for (std::size_t l = 0; l < pools[p]->size(); ++l) {
        const auto [a, b] = pools[p]->slot_ends()[l];  // blocks are in storage order
        const Mat3& c = blocks_[p][l];
        add_block(a, a, c);
        add_block(b, b, c);
        add_block(a, b, c * Real(-1));
        add_block(b, a, c * Real(-1));
      }
    filter();
  }

  // Eigen's CG runs to its end: `stop` is asked before it starts only.
  SolveResult solve(std::vector<Vec3>& rhs, std::vector<Vec3>& dv, Real tolerance,
                    int max_iterations, ForceEvaluator* stop) override {
    for (std::size_t i = 0; i < rhs.size(); ++i)
      if (!free_[i]) rhs[i] = Vec3{};
    const Eigen::Map<const Vector> b(&rhs.data()->x, Eigen::Index(3 * rhs.size()));
    Eigen::Map<Vector> x(&dv.data()->x, Eigen::Index(3 * dv.size()));
    SolveResult r;
    if (stop && stop->stop_requested()) {
      r.stopped = true;
      return r;
    }
    if (b.norm() == 0) {
      x.setZero();
      return r;
    }
    Eigen::ConjugateGradient<Sparse, Eigen::Lower | Eigen::Upper> cg;
    cg.setTolerance(tolerance);
    cg.setMaxIterations(max_iterations);
    cg.compute(matrix_);
    x = cg.solve(b);
    r.iterations = static_cast<int>(cg.iterations());
    r.relative_residual = static_cast<double>(cg.error());
    return r;
  }

  void set_threads(int threads) override { Eigen::setNbThreads(threads); }

  void multiply(const std::vector<Vec3>& u, std::vector<Vec3>& out) override {
    const Eigen::Map<const Vector> uu(&u.data()->x, Eigen::Index(3 * u.size()));
    Eigen::Map<Vector> o(&out.data()->x, Eigen::Index(3 * out.size()));
    o = matrix_ * uu;
  }

 private:
  // The pattern: the diagonal block of every point and the two off-diagonal blocks of every
  // linked pair, built once. block_[(i, j)] gives the value index of entry (3i, 3j).
  void build_pattern() {
    std::vector<std::pair<std::uint32_t, std::uint32_t>> pairs;
    for (std::uint32_t i = 0; i < model_.points.size(); ++i) pairs.push_back({i, i});
    for (const auto& pool : model_.links.pools())
      for (std::size_t l = 0; l < pool->size(); ++l) {
        const auto [a, b] = pool->ends(l);
        pairs.push_back({a, b});
        pairs.push_back({b, a});
      }
    std::sort(pairs.begin(), pairs.end());
    pairs.erase(std::unique(pairs.begin(), pairs.end()), pairs.end());
    std::vector<Eigen::Triplet<Real, std::int64_t>> t;
    t.reserve(pairs.size() * 9);
    for (const auto& [i, j] : pairs)
      for (int r = 0; r < 3; ++r)
        for (int c = 0; c < 3; ++c) t.emplace_back(3 * i + r, 3 * j + c, Real(0));
    const auto n = static_cast<std::int64_t>(3 * model_.points.size());
    matrix_.resize(n, n);
    matrix_.setFromTriplets(t.begin(), t.end());
    matrix_.makeCompressed();
  }

  // Entries of block (i, j) in row 3i + r are contiguous (row-major, 3 columns): find the
  // start of row 3i + r's run for column 3j by binary search in that row.
  std::int64_t entry(std::uint32_t i, std::uint32_t j, int r) const {
    const std::int64_t row = 3 * std::int64_t(i) + r;
    const std::int64_t* cols = matrix_.innerIndexPtr();
    const std::int64_t begin = matrix_.outerIndexPtr()[row], end = matrix_.outerIndexPtr()[row + 1];
    return std::lower_bound(cols + begin, cols + end, 3 * std::int64_t(j)) - cols;
  }

  void add_block(std::uint32_t i, std::uint32_t j, const Mat3& c) {
    Real* val = matrix_.valuePtr();
    for (int r = 0; r < 3; ++r) {
      const std::int64_t e = entry(i, j, r);
      for (int k = 0; k < 3; ++k) val[e + k] += c.m[r][k];
    }
  }

  // Constraint filtering: rows and columns of fixed points become those of the identity.
  void filter() {
    Real* val = matrix_.valuePtr();
    const std::int64_t* cols = matrix_.innerIndexPtr();
    for (std::int64_t row = 0; row < matrix_.rows(); ++row)
      for (std::int64_t e = matrix_.outerIndexPtr()[row]; e < matrix_.outerIndexPtr()[row + 1]; ++e)
        if (!free_[std::size_t(row / 3)] || !free_[std::size_t(cols[e] / 3)])
          val[e] = cols[e] == row ? Real(1) : Real(0);
  }

  const Model& model_;
  Sparse matrix_;
  std::vector<std::vector<Mat3>> blocks_;
  std::vector<std::uint8_t> free_;
};

}  // namespace

std::unique_ptr<ImplicitSystem> make_eigen_system(const Model& m, int threads) {
  return std::make_unique<EigenSystem>(m, threads);
}

}  // namespace maille
