// The typed pool that stores one link kind (struct of arrays, one record per link) and declares
// its law over batches of links: one virtual call per pool and batch, never per link. The loops
// that run the links live with the solvers that own them (include/maille/link_loops.hpp: forces
// in src/core/link_loops.cpp, conjugate gradients' blocks in src/integrators/cg_link_loops.cpp,
// vertex block descent's terms in src/integrators/vbd_link_loops.cpp); the CPU schedule (bands,
// chunks, colours) and the structured kernel's layout are private to detail/cpu_schedule.hpp and
// detail/structured_grid.hpp. No header here opens an OpenMP construct.
#pragma once

#include <algorithm>
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
#include "maille/detail/vectorise.hpp"
#include "maille/link_kind.hpp"
#include "maille/mat3.hpp"

namespace maille {

class LinkPoolBase {
 public:
  virtual ~LinkPoolBase() = default;
  virtual std::string_view keyword() const = 0;
  std::size_t size() const { return ends_.size(); }
  // Links are numbered by id, in the order they were added (the scene's order); prepare()
  // reorders their storage for the CPU schedule and keeps the ids through a remap. Everything
  // that takes or returns a link index at this interface uses ids.
  LinkEnds ends(std::size_t id) const { return ends_[slot_of_id_[id]]; }
  // Storage order (after prepare()): ends in the order the pool runs them, and the id of each
  // slot. Per-link buffers of the implicit solver are in storage order.
  std::span<const LinkEnds> slot_ends() const { return ends_; }
  std::uint32_t id_of_slot(std::size_t slot) const { return id_of_slot_[slot]; }
  // A pool that gained links since prepare() is not prepared, and the loops refuse to run it.
  bool prepared() const { return schedule_.ready() || ends_.empty(); }
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
  // parallel without atomics, and the sum order per point is fixed (determinism).
  void prepare(std::uint32_t point_count) { prepare_on_grids(point_count, {}); }
  // The same, knowing the model's regular grids (Model::prepare): a kind that opts in
  // (`grid_stencil`, detail/structured_grid.hpp) runs its links on them in the structured
  // kernel; every other kind, and every link off the grids, keeps the general schedule.
  virtual void prepare_on_grids(std::uint32_t point_count, std::span<const PointGrid> grids) = 0;
  // Parameters were edited in place (Simulator::edit_parameters calls it): the structured kernel
  // looks again for rows whose records are all equal.
  virtual void parameters_changed() {}

  // The schedule the loops follow (link_loops.hpp): the structured kernel's links in slots
  // 0 .. structured_links() - 1, then the general schedule's chunks from slot schedule_base().
  const detail::CpuSchedule& schedule() const { return schedule_; }
  const detail::StructuredGrid& stencil() const { return stencil_; }
  std::uint32_t schedule_base() const { return base_; }
  std::size_t structured_links() const { return stencil_.size(); }
  std::span<const PointGrid> structured_grids() const { return stencil_.grids(); }
  // Whether no link of the general schedule has an end on the structured kernel's grids (the
  // fused grid step runs them after the grids' rows).
  bool others_off_grids() const { return others_off_grids_; }
  // Sizes the structured kernel's row buffers for `threads` threads, outside parallel regions
  // (the force loops' callers do it before each pass: nothing is allocated once they have grown).
  void reserve_threads(int threads) const {
    if (stencil_.size() > 0) stencil_.reserve(threads);
  }

  // The kind's law over batches of storage slots (what the loops of link_loops.hpp call).
  // Always-active kinds: forces on the first ends of slots [begin, begin + n), ends read from
  // storage, into fx, fy, fz[k] for slot begin + k.
  virtual void gathered_forces(std::size_t begin, std::size_t n, const Vec3* x, const Vec3* v,
                               Real* fx, Real* fy, Real* fz) const = 0;
  // The same for a run whose ends advance by one point per slot (xa[k], xb[k], va[k], vb[k]
  // belong to slot begin + k), contiguous loads; `uniform`: every record of the run equals the
  // first (read once).
  virtual void run_forces(std::size_t begin, std::size_t n, const Vec3* xa, const Vec3* xb,
                          const Vec3* va, const Vec3* vb, bool uniform, Real* fx, Real* fy,
                          Real* fz) const = 0;
  // Conditional kinds: adds the forces of the active links of slots [begin, end) into f (the
  // test is cheap and few links act: no batch); returns how many acted.
  virtual std::uint64_t add_active_forces(std::size_t begin, std::size_t end, const Vec3* x,
                                          const Vec3* v, Vec3* f) const = 0;
  // Conditional kinds: active[k] = whether the link of slots[k] acts at x (1) or not (0).
  // Always-active kinds write 1.
  virtual void active_mask(const std::uint32_t* slots, std::size_t n, const Vec3* x,
                           std::uint8_t* active) const = 0;

  // Implicit integration (kinds that define `jacobian`; the loops skip the others).
  virtual bool has_jacobian() const = 0;
  // Definite-mode Jacobians of slots [begin, begin + n) into out[k].
  virtual void jacobians(std::size_t begin, std::size_t n, const Vec3* x, const Vec3* v,
                         LinkJacobian* out) const = 0;
  // Kinds that offer the axial form (AxialTerms, e.g. SpringDamper): true, and their terms
  // from the axis's squared length d2 and dvd = (v_b - v_a) . d of slots[k] into force, iso,
  // axial[k]: one loop the compiler vectorises (a link's square root and division, taken link by
  // link, leave most of a sweep's time waiting on them).
  virtual bool has_axial() const = 0;
  virtual void axial_terms(const std::uint32_t* slots, std::size_t n, const Real* d2,
                           const Real* dvd, Real inv_h, Real* force, Real* iso,
                           Real* axial) const = 0;
  // VBD's terms of slots[k] (force on the first end and J_x + J_v / h, definite mode): the
  // kind's fused block when it has one, else its force and Jacobian.
  virtual void vbd_blocks(const std::uint32_t* slots, std::size_t n, const Vec3* x, const Vec3* v,
                          Real inv_h, LinkBlock* out) const = 0;

  virtual double energy(const Vec3* x) const = 0;
  // Adds, per point, the stiffness and damping seen through this pool's links, counted twice
  // when the other end is free (Gershgorin bound on the eigenvalues of M^-1 K).
  virtual void stability_terms(std::span<const Real> inv_mass, std::span<Real> k_row,
                               std::span<Real> c_row) const = 0;
  virtual WorstLink worst(const Vec3* x, const Vec3* v) const = 0;  // index: the link's id
  virtual std::unique_ptr<LinkPoolBase> clone() const = 0;

  // Conditional kinds: appends the storage slots of the links that may act while each point p
  // stays within allow[p] of x: ends closer than the link's reach (its threshold, or the kind's
  // reach()) plus both ends' allowances. Always-active kinds append nothing.
  virtual void near_slots(const Vec3* x, const Real* allow,
                          std::vector<std::uint32_t>& out) const = 0;
  // The same with one margin for a pair: closer than the threshold (or rest length) plus
  // `margin` (the candidates of a step whose points move less than margin / 2).
  virtual void near_slots(const Vec3* x, Real margin, std::vector<std::uint32_t>& out) const = 0;

 protected:
  std::vector<LinkEnds> ends_;             // [links] storage order
  std::vector<std::uint32_t> slot_of_id_;  // [links] id -> storage slot
  std::vector<std::uint32_t> id_of_slot_;  // [links] storage slot -> id
  detail::CpuSchedule schedule_;           // the links from slot base_ on
  detail::StructuredGrid stencil_;         // the grid links: slots 0 .. base_ - 1
  std::uint32_t base_ = 0;
  bool others_off_grids_ = true;  // no link of the schedule has an end on the stencil's grids
};

template <LinkKind K>
class LinkPool final : public LinkPoolBase {
 public:
  using Params = typename K::Params;

  std::string_view keyword() const override { return K::keyword; }
  const Params& params(std::size_t id) const { return params_[slot_of_id_[id]]; }
  Params& params_for_editing(std::size_t id) {
    stencil_.edited(slot_of_id_[id]);  // its row no longer assumed uniform
    return params_[slot_of_id_[id]];
  }
  std::span<const Params> slot_params() const { return params_; }
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

  void parameters_changed() override {
    if constexpr (kStructured) stencil_.find_uniform(same_record());
  }

  // ---- The law over batches (LinkPoolBase) ----
  // The loops below are functions of their own with restrict pointers: the vectoriser needs to
  // see that the arrays do not overlap.
  void gathered_forces(std::size_t begin, std::size_t n, const Vec3* x, const Vec3* v, Real* fx,
                       Real* fy, Real* fz) const override {
    if constexpr (kAlwaysActive)
      gathered_lanes(ends_.data() + begin, params_.data() + begin, n, x, v, fx, fy, fz);
  }

  void run_forces(std::size_t begin, std::size_t n, const Vec3* xa, const Vec3* xb, const Vec3* va,
                  const Vec3* vb, bool uniform, Real* fx, Real* fy, Real* fz) const override {
    if constexpr (kAlwaysActive) {
      if (uniform)
        run_lanes_uniform(params_[begin], n, xa, xb, va, vb, fx, fy, fz);
      else
        run_lanes(params_.data() + begin, n, xa, xb, va, vb, fx, fy, fz);
    }
  }

  std::uint64_t add_active_forces(std::size_t begin, std::size_t end, const Vec3* x, const Vec3* v,
                                  Vec3* f) const override {
    std::uint64_t active = 0;
    if constexpr (!kAlwaysActive) {
      const LinkEnds* e = ends_.data();
      const Params* p = params_.data();
      for (std::size_t l = begin; l < end; ++l) {
        const std::uint32_t a = e[l].a, b = e[l].b;
        if (!K::is_active(x[a], x[b], p[l])) continue;
        ++active;
        const Vec3 fa = K::force(x[a], x[b], v[a], v[b], p[l]);
        f[a] += fa;
        f[b] -= fa;
      }
    }
    return active;
  }

  void active_mask(const std::uint32_t* slots, std::size_t n, const Vec3* x,
                   std::uint8_t* active) const override {
    for (std::size_t k = 0; k < n; ++k) {
      if constexpr (kAlwaysActive) {
        active[k] = 1;
      } else {
        const auto [a, b] = ends_[slots[k]];
        active[k] = K::is_active(x[a], x[b], params_[slots[k]]) ? 1 : 0;
      }
    }
  }

  static constexpr bool kHasJacobian = requires(const Vec3& q, const Params& p) {
    K::jacobian(q, q, q, q, p, JacobianMode::exact);
  };
  // Optional fused VBD terms (force and J_x + J_v / h in one pass), e.g. SpringDamper::block.
  static constexpr bool kHasBlock = requires(const Vec3& q, const Params& p, Real r) {
    K::block(q, q, q, q, p, r);
  };
  // Optional axial VBD terms (K::axial, e.g. SpringDamper's).
  static constexpr bool kHasAxial = requires(const Params& p, Real r) { K::axial(r, r, p, r); };
  bool has_jacobian() const override { return kHasJacobian; }
  bool has_axial() const override { return kHasAxial; }

  void jacobians(std::size_t begin, std::size_t n, const Vec3* x, const Vec3* v,
                 LinkJacobian* out) const override {
    if constexpr (kHasJacobian)
      for (std::size_t k = 0; k < n; ++k) {
        const auto [a, b] = ends_[begin + k];
        out[k] = K::jacobian(x[a], x[b], v[a], v[b], params_[begin + k], JacobianMode::definite);
      }
  }

  void axial_terms(const std::uint32_t* slots, std::size_t n, const Real* d2, const Real* dvd,
                   Real inv_h, Real* force, Real* iso, Real* axial) const override {
    if constexpr (kHasAxial) {
      constexpr std::size_t kBatch = 64;
      Params par[kBatch];
      for (std::size_t begin = 0; begin < n; begin += kBatch) {
        const std::size_t m = std::min(kBatch, n - begin);
        for (std::size_t k = 0; k < m; ++k) par[k] = params_[slots[begin + k]];
        axial_lanes(m, d2 + begin, dvd + begin, par, inv_h, force + begin, iso + begin,
                    axial + begin);
      }
    }
  }

  void vbd_blocks(const std::uint32_t* slots, std::size_t n, const Vec3* x, const Vec3* v,
                  Real inv_h, LinkBlock* out) const override {
    if constexpr (kHasJacobian)
      for (std::size_t k = 0; k < n; ++k) out[k] = vbd_block(slots[k], x, v, inv_h);
  }

  // Link l's force on a and its block J_x + J_v / h (definite mode), for VBD.
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
    if constexpr (!kAlwaysActive) {
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
  // Kinds that opt in run their grid links in the structured kernel.
  static constexpr bool kStructured = kAlwaysActive && requires { requires K::grid_stencil; };

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

  // Forces of n links, ends gathered (packed square roots and divisions; the scatter is the
  // caller's: the fused gather-compute-scatter loop is bound by the scalar sqrt/div chain and by
  // store-to-load forwarding between links sharing a point).
  static void gathered_lanes(const LinkEnds* __restrict e, const Params* __restrict p,
                             std::size_t n, const Vec3* __restrict x, const Vec3* __restrict v,
                             Real* __restrict fx, Real* __restrict fy, Real* __restrict fz) {
    MAILLE_VECTORISE
    for (std::size_t k = 0; k < n; ++k) {
      const std::uint32_t a = e[k].a, b = e[k].b;
      const Vec3 fa = K::force(x[a], x[b], v[a], v[b], p[k]);
      fx[k] = fa.x;
      fy[k] = fa.y;
      fz[k] = fa.z;
    }
  }
  // Forces of a run: both ends advance by one, contiguous loads and no index array.
  static void run_lanes(const Params* __restrict p, std::size_t n, const Vec3* __restrict xa,
                        const Vec3* __restrict xb, const Vec3* __restrict va,
                        const Vec3* __restrict vb, Real* __restrict fx, Real* __restrict fy,
                        Real* __restrict fz) {
    MAILLE_VECTORISE
    for (std::size_t k = 0; k < n; ++k) {
      const Vec3 fa = K::force(xa[k], xb[k], va[k], vb[k], p[k]);
      fx[k] = fa.x;
      fy[k] = fa.y;
      fz[k] = fa.z;
    }
  }
  // The same on one record (a uniform run reads it once: the same bits as reading each).
  static void run_lanes_uniform(const Params q, std::size_t n, const Vec3* __restrict xa,
                                const Vec3* __restrict xb, const Vec3* __restrict va,
                                const Vec3* __restrict vb, Real* __restrict fx, Real* __restrict fy,
                                Real* __restrict fz) {
    MAILLE_VECTORISE
    for (std::size_t k = 0; k < n; ++k) {
      const Vec3 fa = K::force(xa[k], xb[k], va[k], vb[k], q);
      fx[k] = fa.x;
      fy[k] = fa.y;
      fz[k] = fa.z;
    }
  }
  // The kind's axial terms of n gathered links.
  static void axial_lanes(std::size_t n, const Real* __restrict d2, const Real* __restrict dvd,
                          const Params* __restrict par, Real inv_h, Real* __restrict force,
                          Real* __restrict iso, Real* __restrict axial) {
    if constexpr (kHasAxial)
      for (std::size_t e = 0; e < n; ++e) {
        const AxialTerms t = K::axial(d2[e], dvd[e], par[e], inv_h);
        force[e] = t.force;
        iso[e] = t.iso;
        axial[e] = t.axial;
      }
  }

  std::vector<Params> params_;  // [links] storage order
  // prepare()'s working arrays, kept by pools prepared often (see prepare).
  std::vector<LinkEnds> spare_ends_;
  std::vector<Params> spare_params_;
  std::vector<std::uint32_t> spare_ids_;
  std::vector<std::uint32_t> spare_others_;
  std::vector<LinkEnds> spare_rest_;
  int prepared_count_ = 0;
};

}  // namespace maille
