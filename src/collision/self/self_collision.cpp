// Self-collision: gather the colliding particles, find close pairs with the chosen broad phase
// (cell size tuned by measurement when "auto"), remove topological neighbours, and apply the
// conditional spring-damper per pair. See include/maille/self_collision.hpp.
#include "maille/self_collision.hpp"
#include "maille/intersections.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <sstream>
#include <stdexcept>
#include <string>

#include "broad_phase.hpp"
#include "edge_proximity.hpp"
#include "maille/limits.hpp"
#include "maille/links/conditional.hpp"
#include "maille/links/spring_damper.hpp"
#include "maille/motion_bound.hpp"
#include "maille/profile.hpp"
#include "maille/shared_laws.hpp"
#include "maille/simulator.hpp"
#include "maille/state.hpp"
#include "self_collision_view.hpp"
#include "self_contact_link.hpp"
#include "triangle_contact_terms.hpp"
#include "triangle_proximity.hpp"

namespace maille {

namespace {

// 1 for every point of the named groups (all groups when none is named); the groups exist
// (resolve_self_collision checked them).
std::vector<std::uint8_t> group_mask(const Model& m, const std::vector<std::string>& groups) {
  std::vector<std::uint8_t> in(m.points.size(), 0);
  auto mark = [&](const Group& g) {
    for (std::uint32_t p = g.first; p < g.first + g.count; ++p) in[p] = 1;
  };
  if (groups.empty())
    for (const Group& g : m.groups) mark(g);
  for (const auto& name : groups)
    if (const Group* g = m.group(name)) mark(*g);
  return in;
}

// The free points of the named groups, sorted.
std::vector<std::uint32_t> colliding_points(const Model& m, const std::vector<std::uint8_t>& in) {
  std::vector<std::uint32_t> set;
  for (std::uint32_t p = 0; p < m.points.size(); ++p)
    if (in[p] && m.points.inv_mass[p] > 0) set.push_back(p);
  return set;
}

// Half the shortest link touching the set, at rest (the initial positions): close enough that
// neighbours never touch at rest, far enough that particles cannot slip between two others.
// 0 when no link touches the set.
Real default_radius(const Model& m, const std::vector<std::uint8_t>& in) {
  Real shortest = std::numeric_limits<Real>::max();
  for (const auto& pool : m.links.pools()) {
    if (pool->conditional()) continue;
    for (const LinkEnds& e : pool->slot_ends())
      if ((in[e.a] && m.points.inv_mass[e.a] > 0) || (in[e.b] && m.points.inv_mass[e.b] > 0))
        shortest = std::min(shortest,
                            norm(m.points.initial_position[e.b] - m.points.initial_position[e.a]));
  }
  if (shortest == std::numeric_limits<Real>::max() || shortest <= 0) return 0;
  return shortest / 2;
}

// Points can slip between a group's particles when the contact distance is below half their
// spacing: two particles a spacing apart leave a gap a point of the same group passes through
// without coming within s of either (the 24 x 24 cloth, 3.5 cm apart, with s = 1.2 cm
// folded through itself). The spacing is a particle's nearest linked neighbour at rest, the
// largest over the group. Nothing to say for primitive = "triangles", which closes the gaps.
std::vector<std::string> leak_warnings(const Model& m, const SelfCollisionSettings& s) {
  std::vector<std::string> out;
  if (s.primitive == Primitive::triangles) return out;
  std::vector<const Group*> groups;
  for (const Group& g : m.groups)
    if (s.groups.empty() || std::find(s.groups.begin(), s.groups.end(), g.name) != s.groups.end())
      groups.push_back(&g);
  const auto& x0 = m.points.initial_position;
  std::vector<Real> nearest(m.points.size(), std::numeric_limits<Real>::max());
  for (const auto& pool : m.links.pools()) {
    if (pool->conditional()) continue;
    for (const LinkEnds& e : pool->slot_ends()) {
      const Real d = norm(x0[e.b] - x0[e.a]);
      nearest[e.a] = std::min(nearest[e.a], d);
      nearest[e.b] = std::min(nearest[e.b], d);
    }
  }
  for (const Group* g : groups) {
    Real spacing = 0;
    for (std::uint32_t p = g->first; p < g->first + g->count; ++p)
      if (m.points.inv_mass[p] > 0 && nearest[p] < std::numeric_limits<Real>::max())
        spacing = std::max(spacing, nearest[p]);
    if (!(s.radius < spacing / 2 * (1 - 1e-9))) continue;  // (spacings carry rounding)
    std::ostringstream w;
    w.precision(4);
    w << "radius " << s.radius << " m is below half the rest spacing of group '" << g->name << "' ("
      << spacing << " m): points can slip between its particles and the cloth pass "
      << "through itself; set radius >= " << spacing / 2
      << " m, or primitive = \"triangles\" (docs/scene-format.md, [self_collision])";
    out.push_back(w.str());
  }
  return out;
}

// Vertex block descent at steps above 1/240 s with a topological exclusion: nothing but
// bending keeps a cell from folding over the neighbours the exclusion skips, and an unconverged
// solve at large steps finds those folds (cloth_on_sphere with particle contacts a spacing
// thick crossed in 40 triangle pairs at 1/60 s with 10 sweeps, none at 1/240 s). The thin
// layer of particle-face contacts with no exclusion crossed in none (docs/implicit.md).
std::string fold_warning(const SimulationSettings& sim, const SelfCollisionSettings& s) {
  constexpr double kSafeStep = 1.0 / 240;
  if (sim.integrator != kImplicitEuler || sim.implicit.solver != ImplicitSolver::vbd ||
      s.topological_radius == 0 || sim.step <= kSafeStep * (1 + 1e-9))
    return {};
  std::ostringstream w;
  w.precision(4);
  w << "topological_radius = " << s.topological_radius
    << " under implicit_euler (solver = \"vbd\") at h = " << sim.step
    << " s: the exclusion leaves a cell free to fold over its neighbours, which steps above "
    << kSafeStep << " s let the solve do; use a thin layer: primitive = \"triangles\", "
    << "topological_radius = 0 and a radius a quarter to a third of the spacing "
    << "(docs/implicit.md, \"Self-collision at large steps\")";
  return w.str();
}

constexpr double kCellFactors[] = {1.0, 1.25, 1.5, 2.0, 3.0, 4.0};
constexpr std::uint64_t kBytesPerContact = 160;  // see SelfCollision::max_contacts_
constexpr double kRetuneBox = 1.5;      // re-tune when the box diagonal changes by this factor
constexpr double kRetuneDensity = 2.0;  // ... or the particles per occupied cell

}  // namespace

class SelfCollision {
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

  // apply()'s displacement bounds at x (MotionBound): `share` times the radius for every
  // colliding particle, lowered by the distances of the point-triangle and edge-edge Verlet
  // lists' pairs (bound: by global id). False without both lists (primitive = "points", or a
  // list over its budget): then nothing is bounded.
  bool motion_bounds(const Vec3* x, Real share, std::vector<Real>& bound) const {
    if (!triangles_) return false;
    for (const std::uint32_t p : set_) bound[p] = share * s_.radius;
    const bool faces = triangles_->bound_motion(x, share, bound.data());
    const bool edges = edges_->bound_motion(x, share, bound.data());
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

// ---------------------------------------------------------------------------------------------

SelfCollisionEngine::SelfCollisionEngine(const Model& m, SelfCollisionSettings s)
    : impl_(std::make_unique<SelfCollision>(m, std::move(s))) {}
SelfCollisionEngine::~SelfCollisionEngine() = default;
SelfCollisionEngine::SelfCollisionEngine(SelfCollisionEngine&&) noexcept = default;

std::vector<std::pair<std::uint32_t, std::uint32_t>> SelfCollisionEngine::close_pairs(const Vec3* x,
                                                                                      int threads) {
  return impl_->close_pairs(x, threads);
}
SelfCollisionStats SelfCollisionEngine::apply(const Vec3* x, const Vec3* v, Vec3* f, int threads) {
  return impl_->apply(x, v, f, threads);
}
bool SelfCollisionEngine::motion_bounds(const Vec3* x, Real share, std::vector<Real>& bound) const {
  return impl_->motion_bounds(x, share, bound);
}
const SelfCollisionSettings& SelfCollisionEngine::settings() const {
  return impl_->settings();
}
std::size_t SelfCollisionEngine::particles() const {
  return impl_->particles();
}
std::size_t SelfCollisionEngine::exclusion_bytes() const {
  return impl_->exclusion_bytes();
}
const std::vector<SelfCollisionEngine::TuneRecord>& SelfCollisionEngine::last_tuning() const {
  return impl_->tuning();
}
void SelfCollisionEngine::set_broad_phase(BroadPhase b) {
  impl_->set_broad_phase(b);
}
void SelfCollisionEngine::set_exclusion(Exclusion e) {
  impl_->set_exclusion(e);
}
void SelfCollisionEngine::set_cell_size(Real c) {
  impl_->set_cell_size(c);
}

// ---------------------------------------------------------------------------------------------

namespace {

// The stage: counters into the profile. The tuner's choice stays in the stage, not in the
// State: it is a performance cache that changes no result (every cell size yields the same
// pairs, summed in the same order), so a copied or resumed State re-tunes and still continues
// bit-identically.
// The surface faces whose three corners belong to the self-colliding groups.
std::vector<Triangle> group_faces(const Model& m, const std::vector<std::string>& groups) {
  const std::vector<std::uint8_t> mask = group_mask(m, groups);
  std::vector<Triangle> out;
  for (const auto& t : m.surface.triangles)
    if (mask[t[0]] && mask[t[1]] && mask[t[2]]) out.push_back(t);
  return out;
}

class SelfCollisionStage final : public Stage, public MotionBound {
 public:
  SelfCollisionStage(const Model& m, const SelfCollisionSettings& s)
      : settings_(s), engine_(m, s), warnings_(leak_warnings(m, engine_.settings())) {
    anchored_ = anchored_triangles(m);
    faces_ = group_faces(m, settings_.groups);
    take_members();
  }
  std::string name() const override { return std::string(kSelfCollisionStage); }
  Phase phase() const override { return kSelfCollisionPhase; }
  void model_changed(const Model& m) override {
    engine_.release_exclusion();
    wide_.reset();
    engine_ = SelfCollision(m, settings_);
    warnings_ = leak_warnings(m, engine_.settings());
    anchored_ = anchored_triangles(m);
    faces_ = group_faces(m, settings_.groups);
    take_members();
    last_cell_ = 0;
  }
  // The points a solver's drift guard watches: the colliding particles and the fixed or driven
  // corners of the faces (they do not move inside a solve; the common displacement must suit
  // them too).
  void take_members() {
    members_ = engine_.set();
    for (const auto& f : faces_) members_.insert(members_.end(), f.begin(), f.end());
    std::sort(members_.begin(), members_.end());
    members_.erase(std::unique(members_.begin(), members_.end()), members_.end());
  }

  // [self_collision] check: the pairs of the groups' faces that cross (intersections.hpp), at
  // the stats cadence or every step; every_step stops the run at the first.
  std::string inspect(const Model&, const State& s, Profile& p, bool sampled) override {
    const IntersectionCheck check = settings_.check;
    if (check == IntersectionCheck::off || faces_.empty()) return {};
    if (check == IntersectionCheck::stats && !sampled) return {};
    if (crossing_id_ < 0) crossing_id_ = p.counter("intersecting_pairs");
    crossings_.keep_pairs(1);
    const std::size_t n = crossings_.count(s.x(), faces_);
    p.set_count(crossing_id_, n);
    if (check != IntersectionCheck::every_step || n == 0) return {};
    const auto& pair = crossings_.pairs().front();
    const Triangle &a = faces_[pair[0]], &b = faces_[pair[1]];
    std::ostringstream why;
    why << n << " pair" << (n == 1 ? "" : "s") << " of triangles of the self-colliding groups "
        << "cross (check = \"every_step\"), the first: points " << a[0] << "-" << a[1] << "-"
        << a[2] << " and " << b[0] << "-" << b[1] << "-" << b[2];
    return why.str();
  }
  std::vector<std::string> warnings(const SimulationSettings& s) const override {
    std::vector<std::string> out = warnings_;
    if (const std::string w = fold_warning(s, engine_.settings()); !w.empty()) out.push_back(w);
    return out;
  }

  // Like conditional links: at most 4 contacts at once per particle (a particle in the hollow
  // of a layer below), each against another free particle (counted twice: Gershgorin).
  void stability_terms(std::span<const Real>, std::span<Real> k_row,
                       std::span<Real> c_row) const override {
    const auto& s = engine_.settings();
    for (std::uint32_t p : engine_.set()) {
      k_row[p] += 4 * 2 * s.stiffness;
      c_row[p] += 4 * 2 * s.damping;
    }
  }

  void apply(const Model&, State& s, const StageContext& ctx) override {
    if (!enabled_) return;
    threads_ = ctx.threads;
    const SelfCollisionStats st =
        engine_.apply(s.x().data(), s.v().data(), s.f().data(), ctx.threads);
    last_cell_ = st.cell_size;
    count(ctx, st);
    // The step's first pass: a new step, or its start evaluated again (Simulator::energies()
    // between steps, then step(), with positions a user may have written in between). The
    // intermediate passes of multi-pass schemes (RK4, velocity Verlet) are at later times.
    if (engine_.settings().primitive == Primitive::triangles &&
        (ctx.step != bounded_step_ || ctx.t == bounded_time_))
      take_bounds(s, ctx.step, ctx.t);
  }

  // Explicit schemes, primitive = "triangles": the displacement bounds of the step's first force
  // pass (x_n), kBoundShare of each point's distance to the faces and edges of its lists and of
  // the radius. Two points closing in by at most 0.8 of their distance in a step never meet, and
  // a pair off the lists is farther than the radius at x_n: no triangle passes through another
  // during the step (docs/implicit.md, "Intersection-free cloth: what holds").
  static constexpr Real kBoundShare = Real(0.4);
  void take_bounds(const State& s, std::uint64_t step, double t) {
    const auto x = s.x();
    xn_.assign(x.begin(), x.end());
    bound_.assign(x.size(), std::numeric_limits<Real>::infinity());
    bounded_ = engine_.motion_bounds(x.data(), kBoundShare, bound_);
    bounded_step_ = step;
    bounded_time_ = t;
  }

  // MotionBound: the scheme's move of each colliding point clamped to its bound.
  std::uint64_t bound_motion(const Model& m, State& s, Real h, Profile& profile) override {
    if (!enabled_ || bounded_step_ != s.step) return 0;
    if (clamp_ids_[0] < 0)
      clamp_ids_ = {profile.counter("self_clamped_points"),
                    profile.counter("self_unbounded_steps")};
    profile.set_count(clamp_ids_[1], bounded_ ? 0 : 1);
    if (!bounded_) return 0;
    const auto x = s.x(), v = s.v();
    std::uint64_t clamped = 0;
    for (const std::uint32_t p : engine_.set()) {
      if (!(m.points.inv_mass[p] > 0)) continue;
      const Vec3 dx = x[p] - xn_[p];
      const Real d2 = norm2(dx), b = bound_[p];
      if (!(d2 > b * b)) continue;
      const Vec3 kept = dx * (b / std::sqrt(d2));
      x[p] = xn_[p] + kept;
      v[p] = kept * (Real(1) / h);
      ++clamped;
    }
    profile.set_count(clamp_ids_[0], clamped);
    return clamped;
  }

  // Implicit schemes: this step's candidates within s + margin, once (no explicit pass); the
  // counters give the candidates and those acting at x_n.
  bool finds_contacts() const override { return true; }
  void find_contacts(const Model& m, State& s, const StageContext& ctx, ContactSet& set) override {
    contacts_.clear();
    triangle_terms_.storage().clear();
    triangle_terms_.set_edge_begin(0);
    if (!enabled_) {  // nothing for the solve (not last step's contacts)
      contacts_.prepare(std::uint32_t(s.size()));
      return;
    }
    threads_ = ctx.threads;
    contacts_as_links(m, s, ctx);
    set.add(contacts_);
    const bool triangles = engine_.settings().primitive == Primitive::triangles;
    if (triangles) set.add(triangle_terms_);
    SelfCollisionStats st;
    st.candidate_pairs = contacts_.size() + triangle_terms_.candidates().size();
    const Vec3* x = s.x().data();
    const Real r2 = engine_.settings().radius * engine_.settings().radius;
    for (const auto& [a, b] : contacts_.slot_ends())
      if (norm2(x[b] - x[a]) < r2) ++st.contacts;
    if (triangles) {
      const auto acting = triangle_terms_.touching(x, s.v().data());
      st.triangle_contacts = acting[0];
      st.edge_contacts = acting[1];
    }
    st.cell_size = last_cell_;
    count(ctx, st);
    searches_ = 1;
    count_searches(ctx);
  }

  // A solver's iterate went past a point's drift limit: the same search at the iterate, into the
  // same arrays (the friction's lag taken there too). The margin follows the iterate's motion
  // from x_n, so the pairs closing within the step are found again.
  bool find_contacts_again(const Model& m, State& s, const StageContext& ctx) override {
    if (!enabled_ || engine_.settings().primitive != Primitive::triangles) return false;
    contacts_.clear();
    triangle_terms_.storage().clear();
    triangle_terms_.set_edge_begin(0);
    contacts_as_links(m, s, ctx, true);
    ++searches_;
    count_searches(ctx);
    return true;
  }

  void count_searches(const StageContext& ctx) {
    if (!ctx.profile) return;
    if (searches_id_ < 0) searches_id_ = ctx.profile->counter("self_searches");
    ctx.profile->set_count(searches_id_, searches_);
  }

  void count(const StageContext& ctx, const SelfCollisionStats& st) {
    if (!ctx.profile) return;
    Profile& p = *ctx.profile;
    if (ids_[0] < 0) {
      ids_ = {p.counter("self_candidate_pairs"),   p.counter("self_contacts"),
              p.counter("self_occupied_cells"),    p.counter("self_excluded_pairs"),
              p.counter("self_skipped_cells"),     p.gauge("self_cell_size"),
              p.counter("self_triangle_contacts"), p.gauge("self_model_Pn2"),
              p.counter("self_edge_contacts")};
    }
    p.set_count(ids_[0], st.candidate_pairs);
    p.set_count(ids_[1], st.contacts);
    p.set_count(ids_[2], st.occupied_cells);
    p.set_count(ids_[3], st.excluded);
    p.set_count(ids_[4], st.skipped_cells);
    p.set_gauge(ids_[5], st.cell_size);
    p.set_count(ids_[6], st.triangle_contacts);
    p.set_count(ids_[8], st.edge_contacts);
    // The cost model P n^2 at the resolution used, beside the stage's measured time
    // (ns_self_collision) in every stats.csv row: P occupied cells, n particles per cell.
    const double per_cell =
        double(engine_.particles()) / std::max<double>(double(st.occupied_cells), 1);
    p.set_gauge(ids_[7], double(st.occupied_cells) * per_cell * per_cell);
  }

  std::vector<StageOption> options() const override {
    const auto& s = engine_.settings();
    auto on_off = [](bool b) { return std::string(b ? "on" : "off"); };
    return {{"enabled", {"on", "off"}, on_off(enabled_)},
            {"broad_phase", name_strings<BroadPhase>(), std::string(to_string(s.broad_phase))},
            {"exclusion", name_strings<Exclusion>(), std::string(to_string(s.exclusion))},
            {"draw_contacts", {"on", "off"}, on_off(draw_contacts_)},
            {"draw_cells", {"on", "off"}, on_off(draw_cells_)}};
  }

  void set_option(const std::string& name, const std::string& value) override {
    auto refuse = [&] {
      throw std::invalid_argument("self_collision: option " + name + " cannot be '" + value + "'");
    };
    if (name == "enabled" || name == "draw_contacts" || name == "draw_cells") {
      if (value != "on" && value != "off") refuse();
      (name == "enabled"         ? enabled_
       : name == "draw_contacts" ? draw_contacts_
                                 : draw_cells_) = value == "on";
    } else if (name == "broad_phase") {
      const auto b = parse_name<BroadPhase>(value);
      if (!b) refuse();
      engine_.set_broad_phase(*b);
      settings_.broad_phase = engine_.settings().broad_phase;
    } else if (name == "exclusion") {
      const auto e = parse_name<Exclusion>(value);
      if (!e) refuse();
      engine_.set_exclusion(*e);
      settings_.exclusion = engine_.settings().exclusion;
    } else {
      Stage::set_option(name, value);
    }
  }

  double energy(const Model&, const State& s) override {
    if (!enabled_) return 0;
    // On the threads of the last pass: the per-thread lists keep their size (no allocation).
    return engine_.energy(s.x().data(), s.v().data(), energy_scratch_, s.size(), threads_);
  }

  SelfCollisionView view() const { return {&engine_.settings(), enabled_, engine_.set()}; }

  // Contacts in green, cells as grey-blue wire boxes (at most kMaxCells of them).
  void overlay(const Model&, const State& s, std::vector<OverlaySegment>& out) const override {
    if (!enabled_) return;
    const Vec3* x = s.x().data();
    if (draw_contacts_)
      engine_.for_each_contact([&](std::uint32_t a, std::uint32_t b) {
        out.push_back({x[a], x[b], {0.2f, 1.0f, 0.3f}});
      });
    if (!draw_cells_) return;
    constexpr std::size_t kMaxCells = 4000;
    const auto boxes = engine_.cell_boxes(x, last_cell_);
    for (std::size_t k = 0; k < boxes.size() && k < kMaxCells; ++k) {
      const Vec3 lo = boxes[k].lo, hi = boxes[k].hi;
      auto corner = [&](int i) {
        return Vec3{i & 1 ? hi.x : lo.x, i & 2 ? hi.y : lo.y, i & 4 ? hi.z : lo.z};
      };
      for (int i = 0; i < 8; ++i)
        for (int bit : {1, 2, 4})
          if (!(i & bit)) out.push_back({corner(i), corner(i | bit), {0.45f, 0.6f, 0.85f}});
    }
  }

 private:
  std::vector<Triangle> faces_;  // the groups' surface faces (check)
  IntersectionCount crossings_;
  int crossing_id_ = -1;
  SelfCollisionSettings settings_;
  SelfCollision engine_;
  std::vector<std::string> warnings_;  // leak_warnings of the resolved settings
  std::array<int, 9> ids_{-1, -1, -1, -1, -1, -1, -1, -1, -1};
  std::array<int, 2> clamp_ids_{-1, -1};  // self_clamped_points, self_unbounded_steps
  std::vector<Vec3> xn_;                  // positions of the step's first force pass
  std::vector<Real> bound_;               // each point's displacement bound from xn_ (m)
  std::uint64_t bounded_step_ = ~std::uint64_t{0};
  double bounded_time_ = -1;  // the time of bounded_step_'s first pass
  bool bounded_ = false;      // the bounds of bounded_step_ hold (both Verlet lists were in use)
  bool enabled_ = true, draw_contacts_ = false, draw_cells_ = false;
  std::vector<Vec3> energy_scratch_;  // energy(): the triangles' forces, discarded
  int threads_ = 1;                   // of the last apply()
  // This step's contact candidates as conditional links (same law) with their friction lagged
  // (self_contact_link.hpp), for implicit schemes: the pairs within s + margin, margin covering
  // the step's motion, so that a solve that moves points by a whole step (vertex block descent)
  // still sees every pair that comes within s.
  LinkPool<collision::FrictionalContact> contacts_;
  // primitive = "triangles": this step's point-triangle candidates within s + margin
  collision::TriangleContactTerms triangle_terms_;
  std::unique_ptr<SelfCollision> wide_;  // the same particles and exclusion, radius s + margin
  Real wide_margin_ = 0;

  // How much closer two particles can come during a step: at most h times twice the largest
  // speed relative to the particles' mean velocity (a common motion, a fall under gravity
  // included, brings no pair closer), with a quarter more for the solve's corrections.
  // State memory key (a std::string made once: the step must not allocate).
  inline static const std::string kWideMargin = "self_collision.wide_margin";

  void build_wide(const Model& m, Real margin) {
    SelfCollisionSettings ws = engine_.settings();
    wide_margin_ = margin;
    ws.radius += wide_margin_;
    ws.cell_size = ws.radius;
    ws.primitive = Primitive::points;
    wide_ = std::make_unique<SelfCollision>(m, ws);
  }

  // Triangles with a fixed or driven corner do not follow the particles' common motion (a
  // particle falling onto a pinned cloth): speeds are then taken as they are.
  bool anchored_ = false;
  bool anchored_triangles(const Model& m) const {
    if (engine_.settings().primitive != Primitive::triangles) return false;
    const std::vector<std::uint8_t> in = group_mask(m, engine_.settings().groups);
    for (const auto& t : m.surface.triangles)
      if (in[t[0]] && in[t[1]] && in[t[2]])
        for (const std::uint32_t c : t)
          if (m.points.inv_mass[c] == 0) return true;
    return false;
  }

  // `again`: a search inside the step, at a solver's iterate, with the wide engine of the step's
  // search as it is (its margin caps each pair's; any pair's is at least a quarter radius, all
  // the drift limit needs): neither rebuilt nor its margin kept, so the next step searches as if
  // the iterate had not been seen.
  void contacts_as_links(const Model& m, State& s, const StageContext& ctx, bool again = false) {
    contacts_.clear();
    if (!again || !wide_) take_wide_margin(m, s, ctx);
    search_pairs(s, ctx);
  }

  void take_wide_margin(const Model& m, State& s, const StageContext& ctx) {
    const auto& st = engine_.settings();
    const Real needed =
        collision::motion_margin(s.v().data(), engine_.set(), Real(ctx.h), anchored_);
    // Grown to twice what is needed when too small, shrunk when four times too large (a cloth
    // come to rest): the wide engine (grid and exclusion) is rebuilt rarely, never per step.
    // The margin in use is part of the state (the candidates, and so the solve's summation
    // order, depend on it): a resumed run rebuilds the engine with the margin it had.
    std::vector<double>& kept = s.memory(kWideMargin);
    if (!wide_ && kept.size() == 1) build_wide(m, Real(kept[0]));
    const Real target = std::max(needed, collision::kMinMarginFraction * st.radius);
    if (!wide_ || needed > wide_margin_ || wide_margin_ > 4 * target) build_wide(m, 2 * target);
    kept.assign(1, double(wide_margin_));
  }

  void search_pairs(State& s, const StageContext& ctx) {
    const auto& st = engine_.settings();
    const Vec3* x = s.x().data();
    const Vec3* v = s.v().data();
    wide_->for_each_close_pair(x, ctx.threads, [&](std::uint32_t a, std::uint32_t b) {
      collision::FrictionalContact::Params p;
      p.normal = {st.stiffness, st.damping, st.radius, st.radius};
      p.friction = st.friction;
      // The friction's lag: the normal force and normal of the step's start, as apply() took
      // them (the same expressions, so that the solvers' start-of-step forces match it).
      if (st.friction > 0 && norm2(x[b] - x[a]) < st.radius * st.radius) {
        const Vec3 fn =
            law::contact_normal_law(x[a], x[b], v[a], v[b], st.stiffness, st.damping, st.radius);
        const Vec3 d = x[b] - x[a];
        p.lag_normal = d * (Real(1) / (norm(d) + Real(1e-30)));
        p.lag_force = std::abs(dot(fn, p.lag_normal));
      }
      contacts_.add({a, b}, p);
    });
    contacts_.prepare(std::uint32_t(s.size()));
    triangle_terms_.set_law(st.radius, st.stiffness, st.damping, st.friction);
    std::size_t edge_begin = 0;
    engine_.triangle_candidates(s.x().data(), s.v().data(), Real(ctx.h), wide_margin_, ctx.threads,
                                triangle_terms_.storage(), edge_begin,
                                triangle_terms_.edge_particles());
    triangle_terms_.set_edge_begin(edge_begin);
    triangle_terms_.lag(x, v);
    triangle_terms_.set_drift(kDriftShare * st.radius, members_);
  }
  // Every pair off the candidates was farther than s + m at the search, m >= s / 4 its margin,
  // and closes by at most 0.8 m from the points' predicted motion (m >= 2.5 h times its closing
  // speed, or the wide margin that covers it) plus its two points' drifts from their
  // predictions: drifts below s / 2 each close it by less than s + 0.05 s <= s + m / 5: it
  // cannot meet (docs/implicit.md, "Intersection-free cloth: what holds").
  static constexpr Real kDriftShare = Real(0.5);
  std::uint64_t searches_ = 0;
  int searches_id_ = -1;
  std::vector<std::uint32_t> members_;  // take_members()
  double last_cell_ = 0;
};

}  // namespace

StageProblem resolve_self_collision(const Model& m, SelfCollisionSettings& s) {
  for (const auto& name : s.groups)
    if (!m.group(name)) return {"groups", "self_collision: no group named '" + name + "'"};
  // Problems of the set as a whole are blamed on the groups when named, else on the radius.
  const std::string set_key = s.groups.empty() ? "radius" : "groups";
  const std::vector<std::uint8_t> in = group_mask(m, s.groups);
  bool any_free = false;
  for (std::uint32_t p = 0; p < m.points.size() && !any_free; ++p)
    any_free = in[p] && m.points.inv_mass[p] > 0;
  if (!any_free) return {set_key, "self_collision: no free point in the groups"};
  if (s.radius <= 0) s.radius = default_radius(m, in);
  if (s.radius <= 0)
    return {set_key,
            "self_collision: cannot default the radius (no link among the colliding points): set "
            "radius"};
  if (s.cell_size != 0 && s.cell_size < s.radius)
    return {"cell_size",
            "self_collision: cell_size must be >= radius (" + std::to_string(s.radius) + " m)"};
  return {};
}

std::unique_ptr<Stage> make_self_collision_stage(const Model& m, const SelfCollisionSettings& s) {
  return std::make_unique<SelfCollisionStage>(m, s);
}

SelfCollisionView self_collision_view(const Stage& st) {
  const auto* sc = dynamic_cast<const SelfCollisionStage*>(&st);
  return sc ? sc->view() : SelfCollisionView{};
}

std::uint64_t self_collision_exclusion_bytes(const Model& m,
                                             std::span<const std::uint32_t> particles,
                                             int topological_radius) {
  if (topological_radius == 0 || particles.empty()) return 0;
  const std::vector<std::uint32_t> set(particles.begin(), particles.end());
  const std::uint64_t row =
      collision::TopologicalExclusion::sampled_row_bound(m, set, topological_radius);
  const std::uint64_t n = set.size(), points = m.points.size();
  std::uint64_t link_ends = 0;
  for (const auto& pool : m.links.pools())
    if (!pool->conditional()) link_ends += 2 * pool->size();
  return 4 * (row * n + (n + 1)) +       // the rows and their offsets
         4 * (link_ends + 2 * points) +  // the adjacency (CSR) and the search's marks
         4 * points + 16 * n;            // the local index, each particle's grid cell
}

ExclusionRows self_collision_exclusion_rows(const Model& m,
                                            std::span<const std::uint32_t> particles,
                                            int topological_radius) {
  const std::vector<std::uint32_t> set(particles.begin(), particles.end());
  const collision::TopologicalExclusion rows(m, set, topological_radius, false);
  return {rows.row_offsets(), rows.row_entries()};
}

}  // namespace maille
