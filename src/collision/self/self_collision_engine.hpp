// Internal: the self-collision engine (SelfCollision, behind SelfCollisionEngine's pimpl: the
// particles' and faces' searches, the tuner, the explicit pass) and the group helpers that it
// and the stage (self_collision_stage.cpp) share.
#pragma once

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <sstream>
#include <stdexcept>
#include <string>
#include "broad_phase.hpp"
#include "edge_proximity.hpp"
#include "maille/intersections.hpp"
#include "maille/limits.hpp"
#include "maille/links/conditional.hpp"
#include "maille/links/spring_damper.hpp"
#include "maille/motion_bound.hpp"
#include "maille/profile.hpp"
#include "maille/self_collision.hpp"
#include "maille/shared_laws.hpp"
#include "maille/simulator.hpp"
#include "maille/state.hpp"
#include "self_collision_view.hpp"
#include "self_contact_link.hpp"
#include "triangle_contact_terms.hpp"
#include "triangle_proximity.hpp"

namespace maille {

// 1 for every point of the named groups (all groups when none is named); the groups exist
// (resolve_self_collision checked them).
std::vector<std::uint8_t> group_mask(const Model& m, const std::vector<std::string>& groups);

// The free points of the named groups, sorted.
std::vector<std::uint32_t> colliding_points(const Model& m, const std::vector<std::uint8_t>& in);

// Half the shortest link touching the set, at rest (the initial positions): close enough that
// neighbours never touch at rest, far enough that particles cannot slip between two others.
// 0 when no link touches the set.
Real default_radius(const Model& m, const std::vector<std::uint8_t>& in);

// Points can slip between a group's particles when the contact distance is below half their
// spacing: two particles a spacing apart leave a gap a point of the same group passes through
// without coming within s of either (the 24 x 24 cloth, 3.5 cm apart, with s = 1.2 cm
// folded through itself). The spacing is a particle's nearest linked neighbour at rest, the
// largest over the group. Nothing to say for primitive = "triangles", which closes the gaps.
std::vector<std::string> leak_warnings(const Model& m, const SelfCollisionSettings& s);

// Vertex block descent at steps above 1/240 s with a topological exclusion: nothing but
// bending keeps a cell from folding over the neighbours the exclusion skips, and an unconverged
// solve at large steps finds those folds (cloth_on_sphere with particle contacts a spacing
// thick crossed in 40 triangle pairs at 1/60 s with 10 sweeps, none at 1/240 s). The thin
// layer of particle-face contacts with no exclusion crossed in none (docs/implicit.md).
std::string fold_warning(const SimulationSettings& sim, const SelfCollisionSettings& s);

// The engine: the colliding particles of the groups, their close pairs by the chosen broad
// phase (the cell size tuned by measurement when "auto"), the topological exclusion, and with
// primitive = "triangles" the point-triangle and edge-edge searches.
class SelfCollision {
  static constexpr double kCellFactors[] = {1.0, 1.25, 1.5, 2.0, 3.0, 4.0};
  static constexpr std::uint64_t kBytesPerContact = 160;  // see max_contacts_
  static constexpr double kRetuneBox = 1.5;  // re-tune when the box diagonal changes by this factor
  static constexpr double kRetuneDensity = 2.0;  // ... or the particles per occupied cell

 public:
  SelfCollision(const Model& m, SelfCollisionSettings s) : s_(std::move(s)) {
    if (const StageProblem p = resolve_self_collision(m, s_))
      throw std::invalid_argument(p.message);
    const std::vector<std::uint8_t> mask = group_mask(m, s_.groups);
    set_ = colliding_points(m, mask);
    xs_.resize(set_.size());
    model_ = &m;
    rebuild_exclusion();
    if (s_.primitive == Primitive::triangles) {
      triangles_ = std::make_unique<collision::TriangleProximity>(
          m, set_, mask,
          std::size_t(limits::memory_budget_bytes() /
                      collision::TriangleProximity::kBytesPerContact));
      std::vector<std::array<std::uint32_t, 3>> faces;
      for (const auto& t : m.surface.triangles)
        if (mask[t[0]] && mask[t[1]] && mask[t[2]]) faces.push_back(t);
      edges_ = std::make_unique<collision::EdgeProximity>(
          m, set_, faces, s_.topological_radius,
          std::size_t(limits::memory_budget_bytes() / collision::EdgeProximity::kBytesPerContact));
    }
  }

  const SelfCollisionSettings& settings() const { return s_; }
  std::size_t particles() const { return set_.size(); }
  const std::vector<std::uint32_t>& set() const { return set_; }
  std::size_t exclusion_bytes() const { return exclusion_ ? exclusion_->bytes() : 0; }
  const std::vector<SelfCollisionEngine::TuneRecord>& tuning() const { return tuning_; }

  void set_broad_phase(BroadPhase b) { s_.broad_phase = b; }

  // For drawing: the close pairs of the last pass (global ids, a < b) and the boxes of the
  // cells in use (grid cells around the particles, or the octree's leaves).
  template <class F>
  void for_each_contact(F&& f) const {
    for (std::uint32_t a = 0; a + 1 < rows_.start.size(); ++a)
      for (std::uint32_t k = rows_.start[a]; k < rows_.start[a + 1]; ++k)
        if (rows_.partners[k] > a) f(set_[a], set_[rows_.partners[k]]);
  }
  std::vector<collision::Box> cell_boxes(const Vec3* x, double cell) const {
    if (s_.broad_phase == BroadPhase::hierarchical) return octree_.leaf_boxes();
    std::vector<collision::Box> out;
    if (s_.broad_phase == BroadPhase::brute || cell <= 0) return out;
    std::vector<Vec3> xs(set_.size());
    for (std::size_t k = 0; k < set_.size(); ++k) xs[k] = x[set_[k]];
    const collision::Box box = collision::bounds(xs.data(), std::uint32_t(xs.size()));
    std::vector<std::array<std::int64_t, 3>> cells;
    for (const Vec3& p : xs) {
      const Vec3 q = (p - box.lo) / Real(cell);
      cells.push_back({std::int64_t(q.x), std::int64_t(q.y), std::int64_t(q.z)});
    }
    std::sort(cells.begin(), cells.end());
    cells.erase(std::unique(cells.begin(), cells.end()), cells.end());
    for (const auto& c : cells) {
      const Vec3 lo = box.lo + Vec3{Real(c[0]), Real(c[1]), Real(c[2])} * Real(cell);
      out.push_back({lo, lo + Vec3{Real(cell), Real(cell), Real(cell)}});
    }
    return out;
  }
  void set_cell_size(Real c) {
    s_.cell_size = c;
    tuned_cell_ = 0;
  }
  void set_exclusion(Exclusion e) {
    s_.exclusion = e;
    rebuild_exclusion();
  }
  // Gives back the exclusion's rows before a new engine is built in this one's place, so that
  // the two never hold them at once (hundreds of MB at large radii).
  void release_exclusion() { exclusion_.reset(); }

  // Close pairs into rows_ (CSR by local particle, partners sorted).
  SelfCollisionStats find(const Vec3* x, int threads) {
    for (std::size_t k = 0; k < set_.size(); ++k) xs_[k] = x[set_[k]];
    collision::Query q;
    q.x = xs_.data();
    q.n = std::uint32_t(xs_.size());
    q.r = s_.radius;
    q.exclusion = s_.exclusion == Exclusion::none ? nullptr : exclusion_.get();
    q.signatures = s_.exclusion == Exclusion::signature;
    sinks_.resize(std::size_t(std::max(threads, 1)));
    for (auto& sink : sinks_) sink.cap = 4 * (max_contacts_ / sinks_.size());
    SelfCollisionStats st;
    switch (s_.broad_phase) {
      case BroadPhase::brute:
        run([&] { collision::brute_pairs(q, sinks_, threads); });
        break;
      case BroadPhase::hierarchical:
        run([&] { octree_.find(q, sinks_, threads); });
        st.occupied_cells = octree_.occupied();
        st.cell_size = s_.radius;
        break;
      case BroadPhase::uniform:
      case BroadPhase::hashed:
        st.cell_size = grid_pass(q, threads);
        st.occupied_cells =
            s_.broad_phase == BroadPhase::uniform ? uniform_.occupied() : hashed_.occupied();
        break;
    }
    for (const auto& sink : sinks_) {
      st.candidate_pairs += sink.tested;
      st.excluded += sink.excluded;
      st.skipped_cells += sink.skipped;
      if (sink.full) refuse_contacts();
    }
    rows_.build(sinks_, set_.size());
    st.contacts = rows_.partners.size() / 2;
    return st;
  }

  // Every close, non-excluded pair (global ids, a < b) at positions x, without allocating once
  // the buffers have grown.
  template <class F>
  void for_each_close_pair(const Vec3* x, int threads, F&& f) {
    find(x, threads);
    for_each_contact(f);
  }

  std::vector<std::pair<std::uint32_t, std::uint32_t>> close_pairs(const Vec3* x, int threads) {
    find(x, threads);
    std::vector<std::pair<std::uint32_t, std::uint32_t>> out;
    for (std::uint32_t a = 0; a < set_.size(); ++a)
      for (std::uint32_t k = rows_.start[a]; k < rows_.start[a + 1]; ++k)
        if (rows_.partners[k] > a) out.push_back({set_[a], set_[rows_.partners[k]]});
    std::sort(out.begin(), out.end());
    return out;
  }

  // Point-triangle candidates within `radius` plus their margins, then from `edge_begin` on the
  // edge-edge ones (primitive = "triangles"; none otherwise).
  void triangle_candidates(const Vec3* x, const Vec3* v, Real h, Real max_margin, int threads,
                           std::vector<std::array<std::uint32_t, 4>>& out, std::size_t& edge_begin,
                           std::vector<std::uint8_t>& edge_particles) {
    out.clear();
    edge_particles.clear();
    edge_begin = 0;
    if (!triangles_) return;
    const collision::TopologicalExclusion* ex =
        s_.exclusion == Exclusion::none ? nullptr : exclusion_.get();
    triangles_->candidates(x, v, s_.radius, h, max_margin, ex, threads, out);
    if (triangles_->full()) refuse_triangle_contacts();
    edge_begin = out.size();
    edges_->candidates(x, v, s_.radius, h, max_margin, ex, threads, out, edge_particles);
    if (edges_->full()) refuse_edge_contacts();
  }

  // The candidates of the `moved` points (mask by global id) within `reach` at x
  // (TriangleProximity::candidates_near), added where `out` lacks them: point-triangle ones at
  // the end of its point-triangle part, edge-edge ones at its end. What `out` holds stays, in
  // its order (a solver's search again around the points past their drift limit).
  void triangle_candidates_near(const Vec3* x, const std::uint8_t* moved, Real reach, int threads,
                                std::vector<std::array<std::uint32_t, 4>>& out,
                                std::size_t& edge_begin,
                                std::vector<std::uint8_t>& edge_particles) {
    if (!triangles_) return;
    const collision::TopologicalExclusion* ex =
        s_.exclusion == Exclusion::none ? nullptr : exclusion_.get();
    triangles_->candidates_near(x, moved, reach, ex, near_found_);
    if (triangles_->full()) refuse_triangle_contacts();
    near_edges_.clear();
    near_bits_.clear();
    edges_->candidates_near(x, moved, reach, ex, threads, near_edges_, near_bits_);
    if (edges_->full()) refuse_edge_contacts();
    const auto begin = out.begin(), split = out.begin() + std::ptrdiff_t(edge_begin);
    merged_.assign(begin, split);
    append_missing(begin, split, near_found_, merged_, nullptr, nullptr);
    const std::size_t new_begin = merged_.size();
    merged_.insert(merged_.end(), split, out.end());
    append_missing(split, out.end(), near_edges_, merged_, &near_bits_, &edge_particles);
    out.swap(merged_);
    edge_begin = new_begin;
  }

  // The contacts' potential at x: 1/2 k (s - d)^2 per close pair (in a < b order) and per
  // particle-triangle contact (counted as apply() pushes them: a shared edge or corner once).
  // The triangles' pass runs apply's search into `scratch` (forces discarded).
  double energy(const Vec3* x, const Vec3* v, std::vector<Vec3>& scratch, std::size_t points,
                int threads) {
    const double r = s_.radius, k = s_.stiffness;
    double e = 0;
    for_each_close_pair(x, threads, [&](std::uint32_t a, std::uint32_t b) {
      const double gap = r - double(norm(x[b] - x[a]));
      if (gap > 0) e += 0.5 * k * gap * gap;
    });
    if (!triangles_) return e;
    scratch.assign(points, Vec3{});
    triangles_->apply(x, v, scratch.data(), {s_.radius, s_.stiffness, s_.damping, s_.friction},
                      s_.exclusion == Exclusion::none ? nullptr : exclusion_.get(), threads);
    if (triangles_->full()) refuse_triangle_contacts();
    edges_->apply(x, v, scratch.data(), {s_.radius, s_.stiffness, s_.damping, s_.friction},
                  s_.exclusion == Exclusion::none ? nullptr : exclusion_.get(), threads);
    if (edges_->full()) refuse_edge_contacts();
    return e + triangles_->energy(s_.stiffness) + edges_->energy(s_.stiffness);
  }

 private:
  // The entries of `found` not in [first, last), appended to `to` in their order (with their
  // `bits` to `bits_to` when given).
  using Quad = std::array<std::uint32_t, 4>;
  void append_missing(std::vector<Quad>::const_iterator first,
                      std::vector<Quad>::const_iterator last, const std::vector<Quad>& found,
                      std::vector<Quad>& to, const std::vector<std::uint8_t>* bits,
                      std::vector<std::uint8_t>* bits_to) {
    // The found are few (around a few points), the held many: the found sorted, each held
    // entry looked up among them.
    order_.resize(found.size());
    for (std::size_t i = 0; i < found.size(); ++i) order_[i] = std::uint32_t(i);
    std::sort(order_.begin(), order_.end(),
              [&](std::uint32_t a, std::uint32_t b) { return found[a] < found[b]; });
    present_.assign(found.size(), 0);
    for (auto it = first; it != last; ++it) {
      const auto at =
          std::lower_bound(order_.begin(), order_.end(), *it,
                           [&](std::uint32_t i, const Quad& q) { return found[i] < q; });
      if (at != order_.end() && found[*at] == *it) present_[*at] = 1;
    }
    for (std::size_t i = 0; i < found.size(); ++i) {
      if (present_[i]) continue;
      to.push_back(found[i]);
      if (bits) bits_to->push_back((*bits)[i]);
    }
  }
  std::vector<Quad> near_found_, near_edges_, merged_;  // triangle_candidates_near()
  std::vector<std::uint8_t> near_bits_, present_;
  std::vector<std::uint32_t> order_;

 public:
  // apply()'s displacement bounds at x (MotionBound): `share` times the radius for every
  // colliding particle, lowered by the distances of the point-triangle and edge-edge Verlet
  // lists' pairs (bound: by global id). False without both lists (primitive = "points", or a
  // list over its budget): then nothing is bounded.
  bool motion_bounds(const Vec3* x, Real share, std::vector<Real>& bound) const {
    if (!triangles_) return false;
    for (const std::uint32_t p : set_) bound[p] = share * s_.radius;
    const bool faces = triangles_->bound_motion(x, share, s_.radius, bound.data());
    const bool edges = edges_->bound_motion(x, share, s_.radius, bound.data());
    return faces && edges;
  }

  // Each particle sums its own contacts in its partners' order: no atomics, and the same sums
  // whatever the broad phase, the cell size or the thread count.
  SelfCollisionStats apply(const Vec3* x, const Vec3* v, Vec3* f, int threads) {
    const SelfCollisionStats st = find(x, threads);
    const auto n = static_cast<std::int64_t>(set_.size());
    const Real r = s_.radius, k = s_.stiffness, z = s_.damping, mu = s_.friction;
#pragma omp parallel for schedule(static) num_threads(threads) if (threads > 1)
    for (std::int64_t a = 0; a < n; ++a) {
      const std::uint32_t pa = set_[std::size_t(a)];
      Vec3 sum{};
      for (std::uint32_t e = rows_.start[std::size_t(a)]; e < rows_.start[std::size_t(a) + 1];
           ++e) {
        const std::uint32_t pb = set_[rows_.partners[e]];
        // The laws the GPU runs too (include/maille/detail/link_laws.glsl).
        const Vec3 fn = law::contact_normal_law(x[pa], x[pb], v[pa], v[pb], k, z, r);
        sum += fn;
        if (mu > 0)  // Coulomb-like: mu |F_n| along the tangential relative velocity
          sum += law::contact_friction_law(x[pa], x[pb], v[pa], v[pb], fn, mu, kSelfCollisionSlip);
      }
      f[pa] += sum;
    }
    if (!triangles_) return st;
    SelfCollisionStats out = st;
    out.triangle_contacts =
        triangles_->apply(x, v, f, {r, k, z, mu},
                          s_.exclusion == Exclusion::none ? nullptr : exclusion_.get(), threads);
    if (triangles_->full()) refuse_triangle_contacts();
    out.edge_contacts =
        edges_->apply(x, v, f, {r, k, z, mu},
                      s_.exclusion == Exclusion::none ? nullptr : exclusion_.get(), threads);
    if (edges_->full()) refuse_edge_contacts();
    return out;
  }

 private:
  template <class F>
  double run(F&& f) {
    for (auto& s : sinks_) s.clear();
    const auto t0 = std::chrono::steady_clock::now();
    f();
    return double(std::chrono::nanoseconds(std::chrono::steady_clock::now() - t0).count());
  }

  // Uniform or hashed grid at the fixed cell size, or at the tuned one. The tuner runs every
  // candidate size (each gives the same pairs), keeps the fastest, and logs the P n^2 model's
  // prediction beside the measured time; it runs again when the box or the density drifts.
  double grid_pass(const collision::Query& q, int threads) {
    auto pass = [&](Real c, double& used) {
      return run([&] {
        used = s_.broad_phase == BroadPhase::uniform ? uniform_.find(q, c, sinks_, threads)
                                                     : hashed_.find(q, c, sinks_, threads);
      });
    };
    auto occupied = [&] {
      return double(s_.broad_phase == BroadPhase::uniform ? uniform_.occupied()
                                                          : hashed_.occupied());
    };
    double used = 0;
    if (s_.cell_size > 0) {
      pass(s_.cell_size, used);
      return used;
    }
    const collision::Box box = collision::bounds(q.x, q.n);
    const double diag = double(norm(box.hi - box.lo)) + 1e-12;
    const bool drifted =
        tuned_cell_ > 0 && (diag > tuned_diag_ * kRetuneBox || diag < tuned_diag_ / kRetuneBox);
    if (tuned_cell_ > 0 && !drifted) {
      pass(Real(tuned_cell_), used);
      const double density = double(q.n) / std::max(occupied(), 1.0);
      if (density > tuned_density_ * kRetuneDensity || density < tuned_density_ / kRetuneDensity)
        tuned_cell_ = 0;  // next step re-tunes
      return used;
    }
    tuning_.clear();
    double best = std::numeric_limits<double>::max();
    for (double factor : kCellFactors) {
      SelfCollisionEngine::TuneRecord rec;
      rec.measured_ns = pass(Real(factor) * s_.radius, used);
      rec.cell_size = used;
      rec.occupied = std::uint64_t(occupied());
      const double per_cell = double(q.n) / std::max(occupied(), 1.0);
      rec.predicted = occupied() * per_cell * per_cell;  // P n^2
      tuning_.push_back(rec);
      if (rec.measured_ns < best) {
        best = rec.measured_ns;
        tuned_cell_ = used;
        tuned_density_ = per_cell;
      }
    }
    tuned_diag_ = diag;
    for (auto& rec : tuning_) rec.chosen = rec.cell_size == tuned_cell_;
    // Once more at the chosen size, so that this step's counters (occupied cells, cell size)
    // describe the resolution kept (the pairs are the same at every size).
    pass(Real(tuned_cell_), used);
    return used;
  }

  // Contacts are bounded by the memory budget (limits.hpp: half the physical memory, or of the
  // address-space limit), at kBytesPerContact each: the sinks (both orders, with the slack of
  // a growing vector), the rows, and an implicit scheme's contact links.
  // (Asked once per engine: the budget reads the environment and makes system calls.)
  std::size_t max_contacts_ = std::size_t(limits::memory_budget_bytes() / kBytesPerContact);
  [[noreturn]] void refuse_contacts() const {
    std::ostringstream why;
    why << "self_collision: more than " << max_contacts_ << " contact pairs (" << kBytesPerContact
        << " bytes each, above the memory budget of "
        << double(limits::memory_budget_bytes()) / double(1 << 30) << " GiB) among " << set_.size()
        << " particles: the radius " << s_.radius
        << " m takes in most of them; lower [self_collision] radius";
    throw std::invalid_argument(why.str());
  }
  // The same bound for primitive = "triangles" (triangle_proximity.hpp).
  [[noreturn]] void refuse_triangle_contacts() const {
    std::ostringstream why;
    why << "self_collision: more than " << triangles_->max_contacts()
        << " particle-triangle contact pairs (" << collision::TriangleProximity::kBytesPerContact
        << " bytes each, above the memory budget of "
        << double(limits::memory_budget_bytes()) / double(1 << 30) << " GiB) among " << set_.size()
        << " particles and " << triangles_->triangles() << " triangles: the radius " << s_.radius
        << " m takes in most of them; lower [self_collision] radius";
    throw std::invalid_argument(why.str());
  }

  // And for its edge pairs (edge_proximity.hpp).
  [[noreturn]] void refuse_edge_contacts() const {
    std::ostringstream why;
    why << "self_collision: more than " << edges_->max_contacts() << " edge-edge contact pairs ("
        << collision::EdgeProximity::kBytesPerContact << " bytes each, above the memory budget of "
        << double(limits::memory_budget_bytes()) / double(1 << 30) << " GiB) among "
        << edges_->edges() << " edges: the radius " << s_.radius
        << " m takes in most of them; lower [self_collision] radius";
    throw std::invalid_argument(why.str());
  }

  void rebuild_exclusion() {
    if (s_.exclusion == Exclusion::none) return;
    exclusion_ = std::make_unique<collision::TopologicalExclusion>(
        *model_, set_, s_.topological_radius, s_.exclusion == Exclusion::signature);
  }

  SelfCollisionSettings s_;
  const Model* model_ = nullptr;
  std::vector<std::uint32_t> set_;  // [n] global ids of the colliding particles
  std::vector<Vec3> xs_;            // [n] their positions, gathered each pass
  std::unique_ptr<collision::TopologicalExclusion> exclusion_;
  collision::UniformGrid uniform_;
  collision::HashedGrid hashed_;
  collision::Octree octree_;
  std::unique_ptr<collision::TriangleProximity> triangles_;
  std::unique_ptr<collision::EdgeProximity> edges_;  // with triangles_: the faces' edge pairs
  std::vector<collision::Sink> sinks_;               // one per thread
  collision::PartnerRows rows_;                      // close partners per point
  std::vector<SelfCollisionEngine::TuneRecord> tuning_;
  double tuned_cell_ = 0, tuned_diag_ = 0, tuned_density_ = 0;
};

}  // namespace maille
