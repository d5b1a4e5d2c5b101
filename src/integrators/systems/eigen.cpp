// Assembled alternative for implicit Euler: the same matrix in an Eigen sparse matrix (3x3
// blocks for every point, every linked pair and every pair the step's contacts couple), values
// refilled each step from the link and contact blocks, solved by Eigen's ConjugateGradient with a
// diagonal preconditioner. Kept to measure against the matrix-free solver (docs/benchmarks.md) and
// to cross-check it in tests; Eigen's CG allocates its work vectors on every solve.
#include <Eigen/IterativeLinearSolvers>
#include <Eigen/Sparse>
#include <algorithm>
#include <array>
#include <cstdint>
#include <vector>

#include "../contact_blocks.hpp"
#include "../implicit_system.hpp"
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
    for (std::uint32_t i = 0; i < n; ++i)
      if (free_[i]) free_list_.push_back(i);
    sink_.assign(n, Vec3{});
    model_pairs();
    build_pattern();
    for (const auto& pool : m.links.pools()) blocks_.emplace_back(pool->size());
  }

  // Transient links (stages' contacts) change the sparsity pattern every step: this solver
  // leaves them explicit (the matrix-free solver takes them), and point contacts too.
  // The model's link blocks and the step's contact set: its pairs' blocks, its stencils'
  // couplings (four points each) and its obstacles' diagonal blocks. The contacts change the
  // sparsity pattern, so it is rebuilt, with the model's pairs, in every step that has contacts
  // (this solver allocates on every solve anyway: it is the reference the matrix-free solver is
  // checked against, not the fast path).
  void linearise(const Model& m, const State& s, Real h, Vec3* rhs,
                 const ContactSet& set) override {
    const auto pools = m.links.pools();
    const Vec3* x = s.x().data();
    const Vec3* v = s.v().data();
    for (std::size_t p = 0; p < pools.size(); ++p)
      implicit_blocks(*pools[p], x, v, h, blocks_[p].data(), rhs);
    const auto pairs = set.pairs();
    if (pair_blocks_.size() < pairs.size()) pair_blocks_.resize(pairs.size());
    for (std::size_t p = 0; p < pairs.size(); ++p) {
      pair_blocks_[p].resize(pairs[p]->size());
      implicit_blocks(*pairs[p], x, v, h, pair_blocks_[p].data(), rhs);
    }
    take_stencils(s, h, rhs, set.stencils());
    const bool obstacles = obstacles_.take(set.obstacles(), s, h, free_list_, rhs);
    const bool contacts = !pairs.empty() || !couplings_.empty();
    if (contacts || contact_pattern_) build_pattern(pairs);
    contact_pattern_ = contacts;
    Real* val = matrix_.valuePtr();
    std::fill(val, val + matrix_.nonZeros(), Real(0));
    const Real drag = h * m.fields.air_drag;
    for (std::uint32_t i = 0; i < m.points.size(); ++i)
      add_block(i, i, Mat3::identity() * (m.points.mass[i] * (1 + drag)));
    for (std::size_t p = 0; p < pools.size(); ++p) add_pool(*pools[p], blocks_[p]);
    for (std::size_t p = 0; p < pairs.size(); ++p) add_pool(*pairs[p], pair_blocks_[p]);
    for (const StencilCoupling& c : couplings_)
      for (std::size_t i = 0; i < 4; ++i)
        for (std::size_t j = 0; j < 4; ++j)
          add_block(c.ids[i], c.ids[j], c.block * (c.c[i] * c.c[j]));
    if (obstacles)
      for (const std::uint32_t i : free_list_) add_block(i, i, obstacles_.blocks[i]);
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
  // The model's pairs: the diagonal block of every point and the two off-diagonal blocks of
  // every linked pair (sorted, once).
  void model_pairs() {
    for (std::uint32_t i = 0; i < model_.points.size(); ++i) model_pairs_.push_back({i, i});
    for (const auto& pool : model_.links.pools())
      for (std::size_t l = 0; l < pool->size(); ++l) {
        const auto [a, b] = pool->ends(l);
        model_pairs_.push_back({a, b});
        model_pairs_.push_back({b, a});
      }
    std::sort(model_pairs_.begin(), model_pairs_.end());
    model_pairs_.erase(std::unique(model_pairs_.begin(), model_pairs_.end()), model_pairs_.end());
  }

  // The pattern: the model's pairs, and the contact set's (its pairs' ends, every two points of
  // a stencil coupling). block_[(i, j)] gives the value index of entry (3i, 3j).
  void build_pattern(std::span<const LinkPoolBase* const> contact_pairs = {}) {
    std::vector<std::pair<std::uint32_t, std::uint32_t>> pairs = model_pairs_;
    for (const LinkPoolBase* pool : contact_pairs)
      for (const auto& e : pool->slot_ends()) {
        pairs.push_back({e.a, e.b});
        pairs.push_back({e.b, e.a});
      }
    for (const StencilCoupling& c : couplings_)
      for (const std::uint32_t i : c.ids)
        for (const std::uint32_t j : c.ids) pairs.push_back({i, j});
    std::sort(pairs.begin(), pairs.end());
    pairs.erase(std::unique(pairs.begin(), pairs.end()), pairs.end());
    std::vector<Eigen::Triplet<Real, std::int64_t>> t;
    t.reserve(pairs.size() * 9);
    for (const auto& [i, j] : pairs)
      for (int r = 0; r < 3; ++r)
        for (int c = 0; c < 3; ++c) t.emplace_back(3 * i + r, 3 * j + c, Real(0));
    const auto n = static_cast<std::int64_t>(3 * model_.points.size());
    matrix_ = Sparse(n, n);
    matrix_.setFromTriplets(t.begin(), t.end());
    matrix_.makeCompressed();
  }

  // A pool's blocks C per link: row a (C, -C), row b (-C, C).
  void add_pool(const LinkPoolBase& pool, const std::vector<Mat3>& blocks) {
    const auto ends = pool.slot_ends();  // blocks are in storage order
    for (std::size_t l = 0; l < ends.size(); ++l) {
      const Mat3& c = blocks[l];
      add_block(ends[l].a, ends[l].a, c);
      add_block(ends[l].b, ends[l].b, c);
      add_block(ends[l].a, ends[l].b, c * Real(-1));
      add_block(ends[l].b, ends[l].a, c * Real(-1));
    }
  }

  // The stencils' couplings at the state (h^2 k + h z, friction's h scale) and the right-hand
  // side's h^2 df/dx v = -h^2 K v, as the matrix-free solver takes them.
  void take_stencils(const State& s, Real h, Vec3* rhs, std::span<TriangleContacts* const> all) {
    couplings_.clear();
    const Vec3* x = s.x().data();
    const Vec3* v = s.v().data();
    for (TriangleContacts* t : all) {
      t->linearise(x, v);
      t->couplings(h * h, h, couplings_);
      if (!rhs) continue;
      std::fill(sink_.begin(), sink_.end(), Vec3{});
      t->apply(h * h, 0, v, sink_.data());
      for (const std::uint32_t i : free_list_) rhs[i] -= sink_[i];
    }
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
  std::vector<std::pair<std::uint32_t, std::uint32_t>> model_pairs_;
  bool contact_pattern_ = false;  // the pattern holds the last step's contacts
  std::vector<std::vector<Mat3>> blocks_;
  std::vector<std::vector<Mat3>> pair_blocks_;  // the contact set's pairs, per pool
  std::vector<StencilCoupling> couplings_;      // the stencils' active couplings
  ObstacleBlocks obstacles_;                    // the obstacles' diagonal blocks
  std::vector<Vec3> sink_;
  std::vector<std::uint8_t> free_;
  std::vector<std::uint32_t> free_list_;
};

}  // namespace

void register_system_eigen(ImplicitSystems& systems) {
  systems.add({to_string(ImplicitSolver::eigen), [](const Model& m, int threads) {
                 return std::unique_ptr<ImplicitSystem>(new EigenSystem(m, threads));
               }});
}

}  // namespace maille
