// Matrix-free preconditioned conjugate gradients for implicit Euler. The product A u is one
// pass over the link pools with their stored 3x3 blocks (the same banded, coloured traversal as
// the force pass, so it threads without atomics), plus the diagonal mass term. Block-Jacobi
// preconditioner (3x3 inverse per point). Every buffer is sized at construction: no
// allocation in a step.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

#include "../contact_blocks.hpp"
#include "../implicit_system.hpp"
#include "maille/link_loops.hpp"

namespace maille {

namespace {

class MatrixFreeSystem final : public ImplicitSystem {
 public:
  MatrixFreeSystem(const Model& m, int threads) : model_(m), threads_(threads) {
    const std::size_t n = m.points.size();
    for (const auto& pool : m.links.pools()) blocks_.emplace_back(pool->size());
    free_.resize(n);
    for (std::size_t i = 0; i < n; ++i) free_[i] = m.points.inv_mass[i] > 0;
    for (std::uint32_t i = 0; i < n; ++i)
      if (free_[i]) free_list_.push_back(i);
    sink_.assign(n, Vec3{});
    for (auto* a : {&r_, &z_, &p_, &q_}) a->assign(n, Vec3{});
    mass_.assign(n, 0);
    diagonal_.assign(n, Mat3{});
    partial_.assign(std::max<std::size_t>((n + kDotBlock - 1) / kDotBlock, 1), 0);
  }

  void linearise(const Model& m, const State& s, Real h, Vec3* rhs,
                 const ContactSet& set) override {
    const auto transient = set.pairs();
    const auto pools = m.links.pools();
    const Vec3* x = s.x().data();
    const Vec3* v = s.v().data();
    step_ = h;
    // The contact set's pairs (this step's): blocks grow with them, never shrink.
    transient_.assign(transient.begin(), transient.end());
    if (transient_blocks_.size() < transient_.size()) transient_blocks_.resize(transient_.size());
    for (std::size_t p = 0; p < transient_.size(); ++p)
      if (transient_blocks_[p].size() < transient_[p]->size())
        transient_blocks_[p].resize(transient_[p]->size());
#pragma omp parallel num_threads(threads_) if (threads_ > 1)
    {
      for (std::size_t p = 0; p < pools.size(); ++p)
        implicit_blocks(*pools[p], x, v, h, blocks_[p].data(), rhs);
      for (std::size_t p = 0; p < transient_.size(); ++p)
        implicit_blocks(*transient_[p], x, v, h, transient_blocks_[p].data(), rhs);
    }
    // Diagonal: M (1 + h gamma) (air drag: df/dv = -gamma m) plus every block touching i.
    const Real drag = h * m.fields.air_drag;
    for (std::size_t i = 0; i < mass_.size(); ++i) {
      mass_[i] = m.points.mass[i] * (1 + drag);
      diagonal_[i] = Mat3::identity() * mass_[i];
    }
    for (std::size_t p = 0; p < pools.size(); ++p)
      add_block_diagonal(*pools[p], blocks_[p].data(), diagonal_.data());
    for (std::size_t p = 0; p < transient_.size(); ++p)
      add_block_diagonal(*transient_[p], transient_blocks_[p].data(), diagonal_.data());
    point_contact_blocks(s, h, rhs, set.obstacles());
    triangle_contact_blocks(s, h, rhs, set.stencils());
    for (std::size_t i = 0; i < diagonal_.size(); ++i)
      diagonal_[i] = free_[i] ? inverse_spd(diagonal_[i]) : Mat3::identity();
  }

  // The set's obstacles: h^2 K + h D on each point's own diagonal block (contact_blocks.hpp).
  void point_contact_blocks(const State& s, Real h, Vec3* rhs,
                            std::span<PointContacts* const> contacts) {
    has_point_blocks_ = obstacles_.take(contacts, s, h, free_list_, rhs);
    if (!has_point_blocks_) return;
    for (const std::uint32_t i : free_list_) diagonal_[i] += obstacles_.blocks[i];
  }

  // Stages' point-triangle contacts: (h^2 k + h z) c c^T n n^T over the candidates in contact,
  // kept for the products; the right-hand side's h^2 df/dx v = -h^2 K v.
  void triangle_contact_blocks(const State& s, Real h, Vec3* rhs,
                               std::span<TriangleContacts* const> triangles) {
    triangles_.assign(triangles.begin(), triangles.end());
    const Vec3* x = s.x().data();
    const Vec3* v = s.v().data();
    for (TriangleContacts* t : triangles_) {
      t->linearise(x, v);
      t->add_diagonal(h * h, h, diagonal_.data());
      if (!rhs) continue;
      std::fill(sink_.begin(), sink_.end(), Vec3{});
      t->apply(h * h, 0, v, sink_.data());
      for (const std::uint32_t i : free_list_) rhs[i] -= sink_[i];
    }
  }

  SolveResult solve(std::vector<Vec3>& b, std::vector<Vec3>& dv, Real tolerance, int max_iterations,
                    ForceEvaluator* stop) override {
    SolveResult result;
    bool stopping = false;  // shared: every thread leaves the loop at the same iteration
    const auto n = static_cast<std::int64_t>(b.size());
#pragma omp parallel num_threads(threads_) if (threads_ > 1)
    {
#pragma omp for schedule(static)
      for (std::int64_t i = 0; i < n; ++i) {
        if (!free_[i]) b[i] = Vec3{};
        dv[i] = Vec3{};
        r_[i] = b[i];
        z_[i] = diagonal_[i] * r_[i];
        p_[i] = z_[i];
      }
      const double b_norm = std::sqrt(dot(b, b));
      double rz = dot(r_, z_);
      double r_norm = b_norm;
      int it = 0;
      while (b_norm > 0 && it < max_iterations && r_norm > tolerance * b_norm) {
        if (stop && it % kStopEvery == kStopEvery - 1) {
#pragma omp master
          stopping = stop->stop_requested();  // on the calling thread (Python's signals)
#pragma omp barrier
          if (stopping) break;
        }
        apply(p_, q_);
        // Breakdown (p.Ap not positive: the search direction has vanished to round-off, with a
        // tolerance below what doubles resolve): the last iterate stands. Every thread reads
        // the same sum, so every thread leaves here.
        const double pq = dot(p_, q_);
        if (!(pq > 0) || !(rz > 0)) break;
        const double alpha = rz / pq;
#pragma omp for schedule(static)
        for (std::int64_t i = 0; i < n; ++i) {
          dv[i] += p_[i] * Real(alpha);
          r_[i] -= q_[i] * Real(alpha);
          z_[i] = diagonal_[i] * r_[i];
        }
        const double rz_next = dot(r_, z_);
        r_norm = std::sqrt(dot(r_, r_));
        const double beta = rz_next / rz;
        rz = rz_next;
#pragma omp for schedule(static)
        for (std::int64_t i = 0; i < n; ++i) p_[i] = free_[i] ? z_[i] + p_[i] * Real(beta) : Vec3{};
        ++it;
      }
#pragma omp single
      {
        result.iterations = it;
        result.relative_residual = b_norm > 0 ? r_norm / b_norm : 0;
        result.stopped = stopping;
      }
    }
    return result;
  }

  void set_threads(int threads) override {
    threads_ = threads;
  }

  void multiply(const std::vector<Vec3>& u, std::vector<Vec3>& out) override {
#pragma omp parallel num_threads(threads_) if (threads_ > 1)
    apply(u, out);
  }

 private:
  // out = S A S u: mass diagonal, then every link block, then the filter. Inside a region.
  void apply(const std::vector<Vec3>& u, std::vector<Vec3>& out) {
    const auto n = static_cast<std::int64_t>(u.size());
#pragma omp for schedule(static)
    for (std::int64_t i = 0; i < n; ++i) out[i] = u[i] * mass_[i];
    const auto pools = model_.links.pools();
    for (std::size_t p = 0; p < pools.size(); ++p)
      apply_blocks(*pools[p], blocks_[p].data(), u.data(), out.data());
    for (std::size_t p = 0; p < transient_.size(); ++p)
      apply_blocks(*transient_[p], transient_blocks_[p].data(), u.data(), out.data());
    if (!triangles_.empty()) {
      const Real h = step_;
#pragma omp single
      for (const TriangleContacts* t : triangles_) t->apply(h * h, h, u.data(), out.data());
    }
#pragma omp for schedule(static)
    for (std::int64_t i = 0; i < n; ++i) {
      if (has_point_blocks_) out[i] += obstacles_.blocks[i] * u[i];
      if (!free_[i]) out[i] = Vec3{};
    }
  }

  // Dot product inside (or outside) a parallel region, the same whatever the thread count:
  // sums over fixed blocks of kDotBlock entries, each by one thread in order, then the blocks
  // added in order by every thread, so that every thread gets the same value. (Per-thread sums
  // would change with the split; the default thread count follows the free cores during a run,
  // simulator.hpp, and must not change the result.)
  double dot(const std::vector<Vec3>& a, const std::vector<Vec3>& b) {
    const std::size_t n = a.size();
    const auto blocks = static_cast<std::int64_t>((n + kDotBlock - 1) / kDotBlock);
#pragma omp for schedule(static)
    for (std::int64_t k = 0; k < blocks; ++k) {
      const std::size_t begin = std::size_t(k) * kDotBlock, end = std::min(n, begin + kDotBlock);
      double local = 0;
      for (std::size_t i = begin; i < end; ++i) local += double(maille::dot(a[i], b[i]));
      partial_[std::size_t(k)] = local;
    }  // the loop's barrier: every block is summed
    double sum = 0;
    for (std::int64_t k = 0; k < blocks; ++k) sum += partial_[std::size_t(k)];
#pragma omp barrier  // every thread has read the blocks before the next dot writes them
    return sum;
  }

  static constexpr std::size_t kDotBlock = 1024;
  const Model& model_;
  int threads_;
  std::vector<std::vector<Mat3>> blocks_;            // per pool, per link: C = h dv + h^2 dx
  std::vector<const LinkPoolBase*> transient_;       // this step's stage links
  std::vector<std::vector<Mat3>> transient_blocks_;  // their blocks (grow-only)
  std::vector<std::uint8_t> free_;
  std::vector<std::uint32_t> free_list_;
  ObstacleBlocks obstacles_;  // the set's obstacles: h^2 K + h D per point
  std::vector<Vec3> sink_;    // the stencils' right-hand-side products
  bool has_point_blocks_ = false;
  std::vector<TriangleContacts*> triangles_;  // this step's point-triangle contacts
  Real step_ = 0;                             // h of the last linearisation
  std::vector<Real> mass_;
  std::vector<Mat3> diagonal_;  // inverse diagonal blocks (preconditioner)
  std::vector<Vec3> r_, z_, p_, q_;
  std::vector<double> partial_;
};

}  // namespace

void register_system_matrix_free(ImplicitSystems& systems) {
  systems.add({to_string(ImplicitSolver::matrix_free), [](const Model& m, int threads) {
                 return std::unique_ptr<ImplicitSystem>(new MatrixFreeSystem(m, threads));
               }});
}

}  // namespace maille
