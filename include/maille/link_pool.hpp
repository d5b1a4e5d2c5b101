// The typed pool that stores one link kind (struct of arrays, one record per link) and runs it
// in an inlined loop: one virtual call per pool per step, never per link. The CPU schedule
// (bands, chunks, colours, OpenMP) is private to detail/cpu_schedule.hpp.
#pragma once

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <memory>
#include <span>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

#include "maille/colouring.hpp"
#include "maille/detail/cpu_schedule.hpp"
#include "maille/detail/structured_grid.hpp"
#include "maille/link_kind.hpp"
#include "maille/mat3.hpp"

namespace maille {

class LinkPoolBase {
 public:
  virtual ~LinkPoolBase() = default;
  virtual std::string_view keyword() const = 0;
  virtual std::size_t size() const = 0;
  // Links are numbered by id, in the order they were added (the scene's order); prepare()
  // reorders their storage for the CPU schedule and keeps the ids through a remap. Everything
  // that takes or returns a link index at this interface uses ids.
  virtual LinkEnds ends(std::size_t id) const = 0;
  // Storage order (after prepare()): ends in the order the pool runs them, and the id of each
  // slot. Per-link buffers of the implicit solver are in storage order.
  virtual std::span<const LinkEnds> slot_ends() const = 0;
  virtual std::uint32_t id_of_slot(std::size_t slot) const = 0;
  virtual bool prepared() const = 0;
  // Conditional kinds (with is_active) are contacts, not topology.
  virtual bool conditional() const = 0;
  // The kind's force law in include/maille/detail/link_laws.glsl (shared with the GPU), or empty
  // when the kind runs on the CPU only.
  virtual std::string_view shared_law() const = 0;
  virtual std::vector<ParamInfo> fields() const = 0;
  // Params in `fields()` order; used by the scene reader and the viewer.
  virtual void add_generic(LinkEnds ends, std::span<const Real> params) = 0;
  virtual Real param(std::size_t id, std::size_t field) const = 0;
  virtual void scale_param(std::size_t field, Real factor) = 0;  // live tuning, between steps
  // One link's parameter, between steps (`maille play`'s controls); call parameters_changed()
  // after a batch of them. No allocation.
  virtual void set_param(std::size_t id, std::size_t field, Real value) = 0;
  // Orders and groups links so that no two groups running together share a point (after
  // building, and again after any structural edit: Simulator::edit_model does it): they run in
  // parallel without atomics, and the sum order per point is fixed (determinism). A pool that
  // gained links since is not prepared(), and accumulate() refuses to run it.
  virtual void prepare(std::uint32_t point_count) = 0;
  // The same, knowing the model's regular grids (Model::prepare): a kind that opts in
  // (`grid_stencil`, detail/structured_grid.hpp) runs its links on them in the structured
  // kernel; every other kind, and every link off the grids, keeps the general schedule.
  virtual void prepare_on_grids(std::uint32_t point_count, std::span<const PointGrid> grids) {
    (void)grids;
    prepare(point_count);
  }
  // How many links run in the structured kernel (0 for kinds that do not opt in).
  virtual std::size_t structured_links() const { return 0; }
  // The grids those links are on, and the structured kernel alone: adds their forces into f,
  // or, with a hook, writes the grid points' f (not read) and calls the hook on each finished
  // row (the fused step). Inside a parallel region every thread of the team calls it.
  virtual std::span<const PointGrid> structured_grids() const { return {}; }
  virtual void structured_forces(const Vec3* x, const Vec3* v, Vec3* f,
                                 const detail::StructuredGrid::RowHook* hook) const {
    (void)x, (void)v, (void)f, (void)hook;
  }
  // Whether no link off the structured kernel (the general schedule's) has an end on its grids
  // (false where unknown), and those links alone: adds their forces into f (inside a parallel
  // region the threads split each group). The fused grid step runs them after the grids' rows.
  virtual bool others_off_grids() const { return false; }
  virtual void other_forces(const Vec3* x, const Vec3* v, Vec3* f) const {
    (void)x, (void)v, (void)f;
  }
  // Sizes the structured kernel's row buffers for `threads` threads, outside parallel regions
  // (link_forces does it before each pass: nothing is allocated once they have grown).
  virtual void reserve_threads(int threads) const { (void)threads; }
  // Parameters were edited in place (Simulator::edit_parameters calls it): the structured kernel
  // looks again for rows whose records are all equal.
  virtual void parameters_changed() {}
  // Adds every link's force into f. Callable inside an OpenMP parallel region (orphaned
  // work-sharing): the threads split each group.
  virtual void accumulate(const Vec3* x, const Vec3* v, Vec3* f, LinkCounters& counters) const = 0;
  virtual double energy(const Vec3* x) const = 0;
  // Adds, per point, the stiffness and damping seen through this pool's links, counted twice
  // when the other end is free (Gershgorin bound on the eigenvalues of M^-1 K).
  virtual void stability_terms(std::span<const Real> inv_mass, std::span<Real> k_row,
                               std::span<Real> c_row) const = 0;
  virtual WorstLink worst(const Vec3* x, const Vec3* v) const = 0;  // index: the link's id
  virtual std::unique_ptr<LinkPoolBase> clone() const = 0;

  // Implicit integration (kinds that define `jacobian`; others return false / do nothing).
  virtual bool has_jacobian() const = 0;
  // For every link l (storage order): C_l = h dv + h^2 dx (definite mode) into blocks[l], and, when
  // rhs is not null, the right-hand side term h^2 (df/dx v): rhs_a += h^2 dx (v_b - v_a), rhs_b -=
  // it.
  virtual void implicit_blocks(const Vec3* x, const Vec3* v, Real h, Mat3* blocks,
                               Vec3* rhs) const = 0;
  // out -= (h df/dv + h^2 df/dx) u, link by link: w = C_l (u_b - u_a); out_a -= w; out_b += w.
  virtual void apply_blocks(const Mat3* blocks, const Vec3* u, Vec3* out) const = 0;
  // Adds every C_l to the diagonal blocks of its two points (block-Jacobi preconditioner).
  virtual void add_block_diagonal(const Mat3* blocks, Mat3* diagonal) const = 0;

  // Vertex block descent (src/integrators/implicit_vbd.cpp). For each point i of `points`, the
  // links of this pool at i are the storage slots slots[row[i]] .. slots[row[i + 1] - 1]: adds
  // their forces on i into f[i] and the block -d f_i / d x_i into hessian[i], with velocities
  // that follow positions as in implicit Euler (v = (x - x_n) / h, hence J_x + J_v / h),
  // definite-mode Jacobians (the block stays positive semi-definite). Inactive conditional
  // links add nothing. Points are independent: threads may run disjoint point sets at once.
  virtual void add_point_terms(std::span<const std::uint32_t> points, const std::uint32_t* row,
                               const std::uint32_t* slots, const Vec3* x, const Vec3* v, Real inv_h,
                               Vec3* f, Mat3* hessian) const = 0;
  // The same terms link by link (VBD's coarse correction, vbd_coarse.hpp): every link once, in
  // storage order, its force into f[a] (f[b] gets the opposite), its block into hessian[a],
  // hessian[b] and blocks[l] (zero for an inactive conditional link). One evaluation per link
  // where add_point_terms makes two; the sums are scattered, so one thread runs it.
  virtual void add_link_terms(const Vec3* x, const Vec3* v, Real inv_h, Vec3* f, Mat3* hessian,
                              Mat3* blocks) const = 0;
  // Conditional kinds: appends the storage slots of the links that may act while each point p
  // stays within allow[p] of x: ends closer than the link's reach (its threshold, or the kind's
  // reach()) plus both ends' allowances. Always-active kinds append nothing.
  virtual void near_slots(const Vec3* x, const Real* allow,
                          std::vector<std::uint32_t>& out) const = 0;
  // The same with one margin for a pair: closer than the threshold (or rest length) plus
  // `margin` (the candidates of a step whose points move less than margin / 2).
  virtual void near_slots(const Vec3* x, Real margin, std::vector<std::uint32_t>& out) const = 0;
};

template <LinkKind K>
class LinkPool final : public LinkPoolBase {
 public:
  using Params = typename K::Params;

  std::string_view keyword() const override { return K::keyword; }
  std::size_t size() const override { return ends_.size(); }
  LinkEnds ends(std::size_t id) const override { return ends_[slot_of_id_[id]]; }
  const Params& params(std::size_t id) const { return params_[slot_of_id_[id]]; }
  Params& params_for_editing(std::size_t id) {
    stencil_.edited(slot_of_id_[id]);  // its row no longer assumed uniform
    return params_[slot_of_id_[id]];
  }
  std::span<const LinkEnds> slot_ends() const override { return ends_; }
  std::span<const Params> slot_params() const { return params_; }
  std::uint32_t id_of_slot(std::size_t slot) const override { return id_of_slot_[slot]; }
  bool prepared() const override { return schedule_.ready() || ends_.empty(); }
  bool conditional() const override { return !kAlwaysActive; }
  std::string_view shared_law() const override {
    if constexpr (requires { K::shared_law; })
      return K::shared_law;
    else
      return {};
  }

  // Removes every link (a stage's transient contacts are rebuilt each step); keeps capacity.
  void clear() {
    ends_.clear();
    params_.clear();
    slot_of_id_.clear();
    id_of_slot_.clear();
    schedule_.clear();
    stencil_.clear();
    base_ = 0;
  }

  // Adds a link; its id is the number of links added before it. The pool must be prepared
  // again before it runs (Simulator::edit_model does it).
  std::uint32_t add(LinkEnds e, const Params& p) {
    const auto id = static_cast<std::uint32_t>(ends_.size());
    ends_.push_back(e);
    params_.push_back(p);
    slot_of_id_.push_back(id);
    id_of_slot_.push_back(id);
    schedule_.clear();
    stencil_.clear();
    base_ = 0;
    return id;
  }

  std::vector<ParamInfo> fields() const override {
    std::vector<ParamInfo> out;
    for (const auto& f : K::fields)
      out.push_back({std::string(f.name), std::string(f.unit), std::string(f.doc), f.bound,
                     f.default_value, f.default_is_distance, std::string(f.default_from)});
    return out;
  }

  void add_generic(LinkEnds e, std::span<const Real> values) override {
    Params p{};
    for (std::size_t k = 0; k < K::fields.size() && k < values.size(); ++k)
      p.*(K::fields[k].member) = values[k];
    add(e, p);
  }

  Real param(std::size_t id, std::size_t field) const override {
    return params_[slot_of_id_[id]].*(K::fields[field].member);
  }

  void scale_param(std::size_t field, Real factor) override {
    for (auto& p : params_) p.*(K::fields[field].member) *= factor;
  }

  void set_param(std::size_t id, std::size_t field, Real value) override {
    params_for_editing(id).*(K::fields[field].member) = value;
  }

  // Stores the grid links first, in the structured kernel's order (detail/structured_grid.hpp),
  // then the others in the CPU schedule's order (detail/cpu_schedule.hpp), and remembers where
  // each id went.
  // A pool prepared again and again (a stage's contacts, every step) keeps its working arrays
  // from the third time on and then allocates nothing once they have grown; the others give
  // them back (a cloth's pools would otherwise hold their links twice).
  void prepare(std::uint32_t point_count) override { prepare_on_grids(point_count, {}); }

  void prepare_on_grids(std::uint32_t point_count, std::span<const PointGrid> grids) override {
    std::span<const std::uint32_t> grid_links{};
    if constexpr (kStructured) grid_links = stencil_.select(ends_, grids, spare_others_);
    const std::size_t structured = grid_links.size();
    // The other links, in their current order, are what the CPU schedule orders.
    std::span<const LinkEnds> rest = ends_;
    if (structured > 0) {
      spare_rest_.resize(spare_others_.size());
      for (std::size_t k = 0; k < spare_others_.size(); ++k)
        spare_rest_[k] = ends_[spare_others_[k]];
      rest = spare_rest_;
    }
    const std::span<const std::uint32_t> order = schedule_.order(rest, kAlwaysActive);
    auto source = [&](std::size_t s) -> std::uint32_t {
      if (s < structured) return grid_links[s];
      return structured > 0 ? spare_others_[order[s - structured]] : order[s];
    };
    std::vector<LinkEnds>& e = spare_ends_;
    std::vector<Params>& p = spare_params_;
    std::vector<std::uint32_t>& ids = spare_ids_;
    e.resize(ends_.size());
    p.resize(params_.size());
    ids.resize(ends_.size());
    for (std::size_t s = 0; s < ends_.size(); ++s) {
      const std::uint32_t from = source(s);
      e[s] = ends_[from];
      p[s] = params_[from];
      ids[s] = id_of_slot_[from];
      slot_of_id_[ids[s]] = static_cast<std::uint32_t>(s);
    }
    ends_.swap(e);
    params_.swap(p);
    id_of_slot_.swap(ids);
    base_ = static_cast<std::uint32_t>(structured);
    schedule_.build(std::span<const LinkEnds>(ends_).subspan(structured), point_count);
    if constexpr (kStructured) stencil_.build(ends_, same_record());
    others_off_grids_ = std::none_of(ends_.begin() + structured, ends_.end(),
                                     [&](LinkEnds l) { return on_grids(l.a) || on_grids(l.b); });
    if (++prepared_count_ < 3) {
      std::vector<LinkEnds>().swap(spare_ends_);
      std::vector<Params>().swap(spare_params_);
      std::vector<std::uint32_t>().swap(spare_ids_);
      std::vector<std::uint32_t>().swap(spare_others_);
      std::vector<LinkEnds>().swap(spare_rest_);
      schedule_.release_scratch();
      stencil_.release_scratch();
    }
  }

  std::size_t structured_links() const override { return stencil_.size(); }
  bool others_off_grids() const override { return others_off_grids_; }
  void other_forces(const Vec3* x, const Vec3* v, Vec3* f) const override {
    schedule_.for_each_chunk([&](std::uint32_t c) { run_chunk(c, x, v, f); });
  }
  std::span<const PointGrid> structured_grids() const override { return stencil_.grids(); }
  void reserve_threads(int threads) const override {
    if (stencil_.size() > 0) stencil_.reserve(threads);
  }

  // The structured kernel's strips (detail/structured_grid.hpp): each thread of the team takes
  // a strip of rows of each grid, computes the link rows it shares with its neighbours (two
  // above, its own last two) and calls the hook's strip before a barrier, then its rows in
  // order: link row, sum, hook.
  void structured_forces(const Vec3* x, const Vec3* v, Vec3* f,
                         const detail::StructuredGrid::RowHook* hook) const override {
    if (stencil_.size() == 0) return;
    using detail::StructuredGrid;
    if (StructuredGrid::team_size() == 1 && stencil_.reserved_threads() < 1) stencil_.reserve(1);
    const int team = StructuredGrid::team_size(), t = StructuredGrid::thread_index();
    Real* mine = stencil_.thread_rows(t);
    const std::size_t size = stencil_.link_row_size();
    Real* ring[3] = {mine, mine + size, mine + 2 * size};
    Real* halo[2] = {mine + 3 * size, mine + 4 * size};
    Real* tail[2] = {mine + 5 * size, mine + 6 * size};
    const auto grids = stencil_.grids();
    for (std::size_t g = 0; g < grids.size(); ++g) {
      const PointGrid& grid = grids[g];
      const std::int64_t strips = std::clamp<std::int64_t>(grid.ny / 4, 1, team);
      const bool works = t < strips;
      const std::int64_t r0 = std::int64_t(grid.ny) * t / strips;
      const std::int64_t r1 = std::int64_t(grid.ny) * (t + 1) / strips;
      if (works) {
        for (std::int64_t h = 0; h < 2; ++h) {
          if (r0 - 2 + h >= 0) link_row(g, std::uint32_t(r0 - 2 + h), x, v, halo[h]);
          if (r1 - 2 + h >= r0) link_row(g, std::uint32_t(r1 - 2 + h), x, v, tail[h]);
        }
        if (hook && hook->strip)
          hook->strip(hook->context, g, std::uint32_t(r0), std::uint32_t(r1));
      }
#pragma omp barrier
      if (!works) continue;
      auto buffer = [&](std::int64_t row) -> const Real* {
        if (row < 0) return stencil_.zero_row();
        if (row < r0) return halo[row - (r0 - 2)];
        if (row >= r1 - 2) return tail[row - (r1 - 2)];
        return ring[row % 3];
      };
      for (std::int64_t row = r0; row < r1; ++row) {
        if (row < r1 - 2) link_row(g, std::uint32_t(row), x, v, ring[row % 3]);
        const std::uint32_t first = grid.first + std::uint32_t(row) * grid.nx;
        gather_row(buffer(row), buffer(row - 1), buffer(row - 2), grid.nx, f + first,
                   hook != nullptr, stencil_.families(g));
        if (hook) hook->run(hook->context, g, std::uint32_t(row));
      }
    }
#pragma omp barrier
  }

  void parameters_changed() override {
    if constexpr (kStructured) stencil_.find_uniform(same_record());
  }

  void accumulate(const Vec3* x, const Vec3* v, Vec3* f, LinkCounters& counters) const override {
    std::uint64_t active = 0;  // this thread's count
    structured_forces(x, v, f, nullptr);
    schedule_.for_each_chunk([&](std::uint32_t c) { active += run_chunk(c, x, v, f); });
    if constexpr (requires { K::is_active(x[0], x[0], params_[0]); }) {
#pragma omp atomic
      counters.active += active;
    }
  }

  static constexpr bool kHasJacobian = requires(const Vec3& q, const Params& p) {
    K::jacobian(q, q, q, q, p, JacobianMode::exact);
  };
  // Optional fused VBD terms (force and J_x + J_v / h in one pass), e.g. SpringDamper::block.
  static constexpr bool kHasBlock = requires(const Vec3& q, const Params& p, Real r) {
    K::block(q, q, q, q, p, r);
  };
  bool has_jacobian() const override {
    return kHasJacobian;
  }

  // Optional axial VBD terms (K::axial, e.g. SpringDamper's): add_point_terms runs them in lanes.
  static constexpr bool kHasAxial = requires(const Params& p, Real r) {
    K::axial(r, r, p, r);
  };

  // add_point_terms for kinds with axial terms, in lanes: the links of a run of points are
  // gathered into arrays (the axis from the point to the link's other end, so that the force on
  // the point is force d at either end), the kind's terms computed over the arrays in one loop
  // the compiler vectorises (a link's square root and division, taken link by link, left most
  // of a sweep's time waiting on them), then summed point by point in slot order: the same sums,
  // bit for bit, as K::block link by link (tests/unit/test_link_lanes.cpp).
  void axial_point_terms(std::span<const std::uint32_t> points, const std::uint32_t* row,
                         const std::uint32_t* slots, const Vec3* x, const Vec3* v, Real inv_h,
                         Vec3* f, Mat3* hessian) const {
    constexpr std::size_t kLanes = 64;
    alignas(64) Real dx[kLanes], dy[kLanes], dz[kLanes], d2[kLanes], dvd[kLanes];
    alignas(64) Real force[kLanes], iso[kLanes], axial[kLanes];
    Params par[kLanes];
    std::uint32_t owner[kLanes];
    std::size_t n = 0;
    std::uint32_t current = ~std::uint32_t(0);
    Vec3 fi{};
    Mat3 hi;
    auto commit = [&] {
      if (current == ~std::uint32_t(0)) return;
      f[current] += fi;
      hessian[current] += hi;
    };
    auto flush = [&] {
      axial_lanes(n, d2, dvd, par, inv_h, force, iso, axial);
      for (std::size_t e = 0; e < n; ++e) {
        if (owner[e] != current) {
          commit();
          current = owner[e];
          fi = Vec3{};
          hi = Mat3{};
        }
        const Vec3 d{dx[e], dy[e], dz[e]};
        fi += d * force[e];
        hi += axial_block(d, {force[e], iso[e], axial[e]});
      }
      n = 0;
    };
    for (const std::uint32_t i : points)
      for (std::uint32_t k = row[i]; k < row[i + 1]; ++k) {
        const std::uint32_t l = slots[k];
        const auto [a, b] = ends_[l];
        if constexpr (!kAlwaysActive)
          if (!K::is_active(x[a], x[b], params_[l])) continue;
        const std::uint32_t j = a == i ? b : a;
        const Vec3 d = x[j] - x[i], dv = v[j] - v[i];
        dx[n] = d.x;
        dy[n] = d.y;
        dz[n] = d.z;
        d2[n] = dot(d, d);
        dvd[n] = dot(dv, d);
        par[n] = params_[l];
        owner[n] = i;
        if (++n == kLanes) flush();
      }
    flush();
    commit();
  }

  // add_link_terms in lanes (as axial_point_terms): runs of links in storage order.
  void axial_link_terms(const Vec3* x, const Vec3* v, Real inv_h, Vec3* f, Mat3* hessian,
                        Mat3* blocks) const {
    constexpr std::size_t kLanes = 64;
    alignas(64) Real d2[kLanes], dvd[kLanes], force[kLanes], iso[kLanes], axial[kLanes];
    Vec3 d[kLanes];
    for (std::size_t begin = 0; begin < ends_.size(); begin += kLanes) {
      const std::size_t n = std::min(kLanes, ends_.size() - begin);
      for (std::size_t e = 0; e < n; ++e) {
        const auto [a, b] = ends_[begin + e];
        d[e] = x[b] - x[a];
        d2[e] = dot(d[e], d[e]);
        dvd[e] = dot(v[b] - v[a], d[e]);
      }
      axial_lanes(n, d2, dvd, params_.data() + begin, inv_h, force, iso, axial);
      for (std::size_t e = 0; e < n; ++e) {
        const auto [a, b] = ends_[begin + e];
        const Vec3 fa = d[e] * force[e];
        const Mat3 k = axial_block(d[e], {force[e], iso[e], axial[e]});
        f[a] += fa;
        f[b] -= fa;
        hessian[a] += k;
        hessian[b] += k;
        blocks[begin + e] = k;
      }
    }
  }

  // The kind's axial terms of n gathered links (the loop that vectorises: a function of its
  // own with restrict pointers, as the vectoriser needs to see the arrays do not overlap).
  static void axial_lanes(std::size_t n, const Real* __restrict d2, const Real* __restrict dvd,
                          const Params* __restrict par, Real inv_h, Real* __restrict force,
                          Real* __restrict iso, Real* __restrict axial) {
    for (std::size_t e = 0; e < n; ++e) {
      const AxialTerms t = K::axial(d2[e], dvd[e], par[e], inv_h);
      force[e] = t.force;
      iso[e] = t.iso;
      axial[e] = t.axial;
    }
  }

  // Link l's force on a and its block J_x + J_v / h (definite mode), for VBD: the kind's fused
  // block when it has one, else its force and Jacobian.
  LinkBlock vbd_block(std::size_t l, const Vec3* x, const Vec3* v,
                      Real inv_h) const requires kHasJacobian {
    const auto [a, b] = ends_[l];
    if constexpr (kHasBlock) {
      return K::block(x[a], x[b], v[a], v[b], params_[l], inv_h);
    } else {
      const LinkJacobian j =
          K::jacobian(x[a], x[b], v[a], v[b], params_[l], JacobianMode::definite);
      return {K::force(x[a], x[b], v[a], v[b], params_[l]), j.dx + j.dv * inv_h};
    }
  }

  void implicit_blocks(const Vec3* x, const Vec3* v, Real h, Mat3* blocks,
                       Vec3* rhs) const override {
    if constexpr (kHasJacobian) {
      for_each_range([&](std::size_t begin, std::size_t end) {
        for (std::size_t l = begin; l < end; ++l) {
          const auto [a, b] = ends_[l];
          const LinkJacobian j =
              K::jacobian(x[a], x[b], v[a], v[b], params_[l], JacobianMode::definite);
          blocks[l] = j.dv * h + j.dx * (h * h);
          if (!rhs) continue;
          const Vec3 r = (j.dx * (v[b] - v[a])) * (h * h);
          rhs[a] += r;
          rhs[b] -= r;
        }
      });
    }
  }

  void apply_blocks(const Mat3* blocks, const Vec3* u, Vec3* out) const override {
    if constexpr (kHasJacobian) {
      for_each_range([&](std::size_t begin, std::size_t end) {
        for (std::size_t l = begin; l < end; ++l) {
          const auto [a, b] = ends_[l];
          const Vec3 w = blocks[l] * (u[b] - u[a]);
          out[a] -= w;
          out[b] += w;
        }
      });
    }
  }

  void add_block_diagonal(const Mat3* blocks, Mat3* diagonal) const override {
    for (std::size_t l = 0; l < ends_.size(); ++l) {
      diagonal[ends_[l].a] += blocks[l];
      diagonal[ends_[l].b] += blocks[l];
    }
  }

  void add_point_terms(std::span<const std::uint32_t> points, const std::uint32_t* row,
                       const std::uint32_t* slots, const Vec3* x, const Vec3* v, Real inv_h,
                       Vec3* f, Mat3* hessian) const override {
    if constexpr (kHasAxial) {
      axial_point_terms(points, row, slots, x, v, inv_h, f, hessian);
    } else if constexpr (kHasJacobian) {
      for (const std::uint32_t i : points) {
        Vec3 fi{};
        Mat3 hi;
        for (std::uint32_t k = row[i]; k < row[i + 1]; ++k) {
          const std::uint32_t l = slots[k];
          const auto [a, b] = ends_[l];
          if constexpr (!kAlwaysActive)
            if (!K::is_active(x[a], x[b], params_[l])) continue;
          const LinkBlock blk = vbd_block(l, x, v, inv_h);
          fi += a == i ? blk.force : -blk.force;
          hi += blk.stiffness;
        }
        f[i] += fi;
        hessian[i] += hi;
      }
    }
  }

  void add_link_terms(const Vec3* x, const Vec3* v, Real inv_h, Vec3* f, Mat3* hessian,
                      Mat3* blocks) const override {
    if constexpr (kHasAxial && kAlwaysActive) {
      axial_link_terms(x, v, inv_h, f, hessian, blocks);
    } else if constexpr (kHasJacobian) {
      for (std::size_t l = 0; l < ends_.size(); ++l) {
        const auto [a, b] = ends_[l];
        if constexpr (!kAlwaysActive)
          if (!K::is_active(x[a], x[b], params_[l])) {
            blocks[l] = Mat3{};
            continue;
          }
        const LinkBlock blk = vbd_block(l, x, v, inv_h);
        f[a] += blk.force;
        f[b] -= blk.force;
        hessian[a] += blk.stiffness;
        hessian[b] += blk.stiffness;
        blocks[l] = blk.stiffness;
      }
    }
  }

  void near_slots(const Vec3* x, const Real* allow,
                  std::vector<std::uint32_t>& out) const override {
    if constexpr (!kAlwaysActive) {
      for (std::size_t l = 0; l < ends_.size(); ++l) {
        const Real reach = reach_of(l) + allow[ends_[l].a] + allow[ends_[l].b];
        if (norm2(x[ends_[l].b] - x[ends_[l].a]) < reach * reach)
          out.push_back(static_cast<std::uint32_t>(l));
      }
    }
  }

  void near_slots(const Vec3* x, Real margin, std::vector<std::uint32_t>& out) const override {
    if constexpr (!kAlwaysActive) {
      for (std::size_t l = 0; l < ends_.size(); ++l) {
        const Real reach = rest_hint(l) + margin;
        if (norm2(x[ends_[l].b] - x[ends_[l].a]) < reach * reach)
          out.push_back(static_cast<std::uint32_t>(l));
      }
    }
  }

  double energy(const Vec3* x) const override {
    double sum = 0;
    for (std::size_t l = 0; l < ends_.size(); ++l)
      sum += K::energy(x[ends_[l].a], x[ends_[l].b], params_[l]);
    return sum;
  }

  void stability_terms(std::span<const Real> inv_mass, std::span<Real> k_row,
                       std::span<Real> c_row) const override {
    if constexpr (requires { K::is_active(Vec3{}, Vec3{}, params_[0]); }) {
      conditional_stability_terms(inv_mass, k_row, c_row);
    } else {
      for (std::size_t l = 0; l < ends_.size(); ++l) {
        const auto [a, b] = ends_[l];
        const Real k = K::stiffness(params_[l]), c = K::damping(params_[l]);
        const Real wa = inv_mass[b] > 0 ? 2 : 1, wb = inv_mass[a] > 0 ? 2 : 1;
        k_row[a] += wa * k;
        c_row[a] += wa * c;
        k_row[b] += wb * k;
        c_row[b] += wb * c;
      }
    }
  }

  // A point may hold hundreds of conditional links (one per floor point) of which only a few
  // can be active at once: counting them all would make the bound uselessly small. A point is
  // assumed to touch at most kSimultaneousContacts partners at a time (4: a point resting in the
  // hollow of a square bed of spheres), each as stiff as its stiffest conditional link.
  static constexpr Real kSimultaneousContacts = 4;
  void conditional_stability_terms(std::span<const Real> inv_mass, std::span<Real> k_row,
                                   std::span<Real> c_row) const {
    std::vector<Real> k_max(k_row.size(), 0), c_max(k_row.size(), 0);
    for (std::size_t l = 0; l < ends_.size(); ++l) {
      const auto [a, b] = ends_[l];
      const Real k = K::stiffness(params_[l]), c = K::damping(params_[l]);
      const Real wa = inv_mass[b] > 0 ? 2 : 1, wb = inv_mass[a] > 0 ? 2 : 1;
      k_max[a] = std::max(k_max[a], wa * k);
      c_max[a] = std::max(c_max[a], wa * c);
      k_max[b] = std::max(k_max[b], wb * k);
      c_max[b] = std::max(c_max[b], wb * c);
    }
    for (std::size_t i = 0; i < k_row.size(); ++i) {
      k_row[i] += kSimultaneousContacts * k_max[i];
      c_row[i] += kSimultaneousContacts * c_max[i];
    }
  }

  WorstLink worst(const Vec3* x, const Vec3* v) const override {
    WorstLink w;
    w.badness = -1;
    for (std::size_t l = 0; l < ends_.size(); ++l) {
      const auto [a, b] = ends_[l];
      const Vec3 fa = K::force(x[a], x[b], v[a], v[b], params_[l]);
      Real bad;
      if (!is_finite(x[a]) || !is_finite(x[b]) || !is_finite(fa)) {
        bad = INFINITY;
      } else {
        const Real d = norm(x[b] - x[a]), d0 = rest_hint(l);
        bad = std::abs(d - d0) / std::max<Real>(d0, Real(1e-9));
      }
      if (bad > w.badness) w = {id_of_slot_[l], ends_[l], bad};
    }
    return w;
  }

  std::unique_ptr<LinkPoolBase> clone() const override {
    return std::make_unique<LinkPool<K>>(*this);
  }

  // The distance scale of link l, for strain in diagnostics: a field named rest_length or
  // threshold when the kind has one, else 1 m.
  // The distance below which link l may act: the kind's reach(params) where it declares one
  // (a contact whose lagged friction acts at any distance), else its threshold or rest length.
  Real reach_of(std::size_t l) const {
    if constexpr (requires(const Params& p) { K::reach(p); })
      return K::reach(params_[l]);
    else
      return rest_hint(l);
  }
  Real rest_hint(std::size_t l) const {
    for (const auto& f : K::fields)
      if (f.name == "rest_length" || f.name == "threshold") return params_[l].*(f.member);
    return 1;
  }

 private:
  static constexpr bool kAlwaysActive = !requires(const Vec3& q, const Params& p) {
    K::is_active(q, q, p);
  };
  static constexpr std::size_t kChunk = detail::CpuSchedule::kChunk;
  // Kinds that opt in run their grid links in the structured kernel.
  static constexpr bool kStructured = kAlwaysActive && requires {
    requires K::grid_stencil;
  };

  bool on_grids(std::uint32_t point) const {
    for (const PointGrid& g : stencil_.grids())
      if (point >= g.first && point - g.first < std::uint64_t(g.nx) * g.ny) return true;
    return false;
  }

  // Bit-for-bit equality of two slots' records (a uniform row runs on its first record).
  auto same_record() const {
    return [this](std::uint32_t s, std::uint32_t t) {
      return std::memcmp(&params_[s], &params_[t], sizeof(Params)) == 0;
    };
  }

  // Runs f(begin, end) over the storage slots in ranges no two threads share a point in:
  // the structured kernel's segments, then the schedule's chunks.
  template <class F>
  void for_each_range(F&& f) const {
    if constexpr (kStructured)
      stencil_.for_each_segment([&](std::size_t s) {
        const auto& g = stencil_.segment(s);
        f(std::size_t(g.slot), std::size_t(g.slot) + g.count);
      });
    schedule_.for_each_chunk([&](std::uint32_t c) {
      f(std::size_t(base_) + schedule_.chunk_begin(c), std::size_t(base_) + schedule_.chunk_end(c));
    });
  }

  // Link row j of grid g (detail/structured_grid.hpp): each family's forces along the row,
  // by the column of the first end, zero where there is no link. A segment's ends both advance
  // by one, so positions and velocities are contiguous loads and the loop vectorises with no
  // index array; a uniform segment reads its one record once.
  void link_row(std::size_t g, std::uint32_t j, const Vec3* x, const Vec3* v, Real* out) const {
    const PointGrid& grid = stencil_.grids()[g];
    const std::size_t w = stencil_.width();
    const std::uint32_t row_first = grid.first + j * grid.nx;
    for (std::size_t fam = 0; fam < detail::StructuredGrid::kFamilies.size(); ++fam) {
      // An absent family's buffers are not written: they hold zeros (cut_segments).
      if (!(stencil_.families(g) >> fam & 1)) continue;
      Real* bx = out + fam * 3 * w + 2;  // column c at c + 2
      Real* by = bx + w;
      Real* bz = by + w;
      std::int64_t done = -2;  // columns before this one are written
      auto zero_to = [&](std::int64_t column) {
        for (std::int64_t c = done; c < column; ++c) bx[c] = by[c] = bz[c] = 0;
      };
      const auto [s0, s1] = stencil_.row_segments(g, j, fam);
      for (std::uint32_t s = s0; s < s1; ++s) {
        const auto& seg = stencil_.segment(s);
        const std::int64_t i0 = std::int64_t(seg.a) - row_first;
        zero_to(i0);
        const Params* p = params_.data() + seg.slot;
        const Vec3 *xa = x + seg.a, *xb = x + seg.b, *va = v + seg.a, *vb = v + seg.b;
        Real *ox = bx + i0, *oy = by + i0, *oz = bz + i0;
        const std::size_t n = seg.count;
        if (stencil_.uniform(s)) {
          const Params q = p[0];
#pragma omp simd
          for (std::size_t k = 0; k < n; ++k) {
            const Vec3 fa = K::force(xa[k], xb[k], va[k], vb[k], q);
            ox[k] = fa.x;
            oy[k] = fa.y;
            oz[k] = fa.z;
          }
        } else {
#pragma omp simd
          for (std::size_t k = 0; k < n; ++k) {
            const Vec3 fa = K::force(xa[k], xb[k], va[k], vb[k], p[k]);
            ox[k] = fa.x;
            oy[k] = fa.y;
            oz[k] = fa.z;
          }
        }
        done = i0 + std::int64_t(n);
      }
      zero_to(std::int64_t(grid.nx) + 2);
    }
  }

  // Row j's points sum their links' forces in one fixed order: as first end (row j's buffers,
  // families in order), then as second end (the buffers of rows j - dj at column i - di).
  // `assign`: f = the sum (the fused step, f not cleared), else f += the sum.
  // `present`: the grid's families (StructuredGrid::families); with two (a net's, a flag's
  // without shear and bending) only theirs are summed: the same sums, since an absent family's
  // +0 leaves a sum that starts at +0 (hence is never -0) as it is.
  void gather_row(const Real* r0, const Real* r1, const Real* r2, std::uint32_t nx, Vec3* f,
                  bool assign, std::uint8_t present) const {
    constexpr std::size_t families = detail::StructuredGrid::kFamilies.size();
    static_assert(families == 6);
    const std::size_t w = stencil_.width();
    const Real* rows[3] = {r0, r1, r2};
    const Real* first[3][families];
    const Real* second[3][families];
    for (std::size_t fam = 0; fam < families; ++fam) {
      const auto [di, dj] = detail::StructuredGrid::kFamilies[fam];
      for (std::size_t c = 0; c < 3; ++c) {
        first[c][fam] = r0 + (fam * 3 + c) * w + 2;
        second[c][fam] = rows[dj] + (fam * 3 + c) * w + 2 - di;
      }
    }
    if (std::popcount(present) == 2) {
      const Real* p[3][2];
      const Real* q[3][2];
      for (std::size_t fam = 0, k = 0; fam < families; ++fam)
        if (present >> fam & 1) {
          for (std::size_t c = 0; c < 3; ++c) p[c][k] = first[c][fam], q[c][k] = second[c][fam];
          ++k;
        }
      if (assign)
        gather<true>(p, q, nx, f);
      else
        gather<false>(p, q, nx, f);
      return;
    }
    if (assign)
      gather<true>(first, second, nx, f);
    else
      gather<false>(first, second, nx, f);
  }

  static Real gathered(const Real* const (&p)[2], const Real* const (&q)[2], std::size_t i) {
    Real s = 0;
    s += p[0][i];
    s += p[1][i];
    s -= q[0][i];
    s -= q[1][i];
    return s;
  }

  // One coordinate of point i's sum (gather_row), written out so that the loop vectorises.
  static Real gathered(const Real* const (&p)[6], const Real* const (&q)[6], std::size_t i) {
    Real s = 0;
    s += p[0][i];
    s += p[1][i];
    s += p[2][i];
    s += p[3][i];
    s += p[4][i];
    s += p[5][i];
    s -= q[0][i];
    s -= q[1][i];
    s -= q[2][i];
    s -= q[3][i];
    s -= q[4][i];
    s -= q[5][i];
    return s;
  }

  template <bool kAssign, std::size_t N>
  static void gather(const Real* const (&p)[3][N], const Real* const (&q)[3][N], std::size_t nx,
                     Vec3* f) {
#pragma omp simd
    for (std::size_t i = 0; i < nx; ++i) {
      const Real sx = gathered(p[0], q[0], i), sy = gathered(p[1], q[1], i),
                 sz = gathered(p[2], q[2], i);
      if constexpr (kAssign) {  // by coordinate: a Vec3 copy does not vectorise here
        f[i].x = sx;
        f[i].y = sy;
        f[i].z = sz;
      } else {
        f[i].x += sx;
        f[i].y += sy;
        f[i].z += sz;
      }
    }
  }

  // Forces of one chunk of links. Kinds that are always active compute all forces first in a
  // loop the compiler vectorises (packed sqrt and division; contiguous loads on runs, gathers
  // otherwise), then scatter them: the fused gather-compute-scatter loop is bound by the scalar
  // sqrt/div chain and by store-to-load forwarding between links sharing a point. Conditional
  // kinds test cheaply first and compute only the few active links.
  std::uint64_t run_chunk(std::size_t c, const Vec3* x, const Vec3* v, Vec3* f) const {
    const std::size_t begin = base_ + schedule_.chunk_begin(c),
                      end = base_ + schedule_.chunk_end(c);
    const LinkEnds* e = ends_.data();
    const Params* p = params_.data();
    if constexpr (requires { K::is_active(x[0], x[0], p[0]); }) {
      std::uint64_t active = 0;
      for (std::size_t l = begin; l < end; ++l) {
        const std::uint32_t a = e[l].a, b = e[l].b;
        if (!K::is_active(x[a], x[b], p[l])) continue;
        ++active;
        const Vec3 fa = K::force(x[a], x[b], v[a], v[b], p[l]);
        f[a] += fa;
        f[b] -= fa;
      }
      return active;
    } else {
      Real fx[kChunk], fy[kChunk], fz[kChunk];  // uninitialised on purpose: fully written
      const std::size_t n = end - begin;
      if (schedule_.chunk_is_run(c)) {
        const std::uint32_t a0 = e[begin].a, b0 = e[begin].b;
        const Vec3 *xa = x + a0, *xb = x + b0, *va = v + a0, *vb = v + b0;
#pragma omp simd
        for (std::size_t k = 0; k < n; ++k) {
          const Vec3 fa = K::force(xa[k], xb[k], va[k], vb[k], p[begin + k]);
          fx[k] = fa.x;
          fy[k] = fa.y;
          fz[k] = fa.z;
        }
        Vec3* fa = f + a0;
        Vec3* fb = f + b0;
        for (std::size_t k = 0; k < n; ++k) fa[k] += Vec3{fx[k], fy[k], fz[k]};
        for (std::size_t k = 0; k < n; ++k) fb[k] -= Vec3{fx[k], fy[k], fz[k]};
        return 0;
      }
#pragma omp simd
      for (std::size_t k = 0; k < n; ++k) {
        const std::uint32_t a = e[begin + k].a, b = e[begin + k].b;
        const Vec3 fa = K::force(x[a], x[b], v[a], v[b], p[begin + k]);
        fx[k] = fa.x;
        fy[k] = fa.y;
        fz[k] = fa.z;
      }
      for (std::size_t k = 0; k < n; ++k) {
        const Vec3 fa{fx[k], fy[k], fz[k]};
        f[e[begin + k].a] += fa;
        f[e[begin + k].b] -= fa;
      }
      return 0;
    }
  }

  std::vector<LinkEnds> ends_;             // [links] storage order
  std::vector<Params> params_;             // [links] storage order
  std::vector<std::uint32_t> slot_of_id_;  // [links] id -> storage slot
  std::vector<std::uint32_t> id_of_slot_;  // [links] storage slot -> id
  detail::CpuSchedule schedule_;           // the links from slot base_ on
  detail::StructuredGrid stencil_;         // the grid links: slots 0 .. base_ - 1
  std::uint32_t base_ = 0;
  bool others_off_grids_ = true;  // no link of the schedule has an end on the stencil's grids
  // prepare()'s working arrays, kept by pools prepared often (see prepare).
  std::vector<LinkEnds> spare_ends_;
  std::vector<Params> spare_params_;
  std::vector<std::uint32_t> spare_ids_;
  std::vector<std::uint32_t> spare_others_;
  std::vector<LinkEnds> spare_rest_;
  int prepared_count_ = 0;
};

}  // namespace maille
