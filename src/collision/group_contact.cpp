// Contacts between groups through the self-collision broad phase
// (include/maille/group_contact.hpp): the two groups' points in one uniform grid, pairs on the same
// side or with two fixed ends skipped before their distance is tested, close pairs into per-point
// rows, the conditional law per pair.
#include "maille/group_contact.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

#include "maille/link_pool.hpp"
#include "maille/links/conditional.hpp"
#include "maille/profile.hpp"
#include "maille/shared_laws.hpp"
#include "maille/state.hpp"
#include "self/broad_phase.hpp"

namespace maille {

namespace {

constexpr std::uint8_t kSideB = 1, kFixed = 2;

// One [[contact]] table: its points (A's, then B's), their tags, and this step's close pairs.
class GroupContact {
 public:
  GroupContact(const Model& m, const GroupContactSpec& spec) : spec_(spec) {
    const Group* g[2] = {m.group(spec.a), m.group(spec.b)};
    for (int k = 0; k < 2; ++k)
      if (!g[k])
        throw std::invalid_argument("contact: no group named '" + (k ? spec.b : spec.a) + "'");
    if (g[0]->first < g[1]->first + g[1]->count && g[1]->first < g[0]->first + g[0]->count)
      throw std::invalid_argument("contact: groups '" + spec.a + "' and '" + spec.b +
                                  "' share points");
    bool free[2] = {false, false};
    for (int k = 0; k < 2; ++k)
      for (std::uint32_t p = g[k]->first; p < g[k]->first + g[k]->count; ++p) {
        set_.push_back(p);
        const bool fixed = m.points.inv_mass[p] == 0;
        tag_.push_back(std::uint8_t((k ? kSideB : 0) | (fixed ? kFixed : 0)));
        free[k] = free[k] || !fixed;
      }
    if (!free[0] && !free[1])
      throw std::invalid_argument("contact: groups '" + spec.a + "' and '" + spec.b +
                                  "' hold no free point");
    free_partner_[0] = free[1];
    free_partner_[1] = free[0];
    first_b_ = g[0]->count;
    xs_.resize(set_.size());
    qtag_.resize(set_.size());
    near_.reserve(set_.size());
  }

  const GroupContactSpec& spec() const { return spec_; }
  const std::vector<std::uint32_t>& set() const { return set_; }
  bool side_b(std::size_t local) const { return (tag_[local] & kSideB) != 0; }
  bool partner_may_be_free(std::size_t local) const { return free_partner_[side_b(local)]; }

  // Pairs closer than r into rows (CSR by query point, partners sorted); returns the pairs
  // whose distance was tested. Only the points of each group within r of the other group's
  // bounding box enter the grid (a bead over a drum skin: the bead and the skin under it), which
  // drops no pair closer than r.
  std::uint64_t find(const Vec3* x, Real r, int threads) {
    const collision::Box a = grown_bounds(x, 0, first_b_, r);
    const collision::Box b = grown_bounds(x, first_b_, set_.size(), r);
    near_.clear();
    for (std::size_t k = 0; k < set_.size(); ++k)
      if (inside(k < first_b_ ? b : a, x[set_[k]])) near_.push_back(std::uint32_t(k));
    for (std::size_t q = 0; q < near_.size(); ++q) {
      xs_[q] = x[set_[near_[q]]];
      qtag_[q] = tag_[near_[q]];
    }
    for (auto& s : sinks_) s.clear();
    sinks_.resize(std::size_t(std::max(threads, 1)));
    if (!near_.empty()) {
      collision::Query q;
      q.x = xs_.data();
      q.n = std::uint32_t(near_.size());
      q.r = r;
      q.tag = qtag_.data();
      grid_.find(q, r, sinks_, threads);
    }
    std::uint64_t tested = 0;
    for (const auto& s : sinks_) tested += s.tested;
    rows_.build(sinks_, near_.size());
    return tested;
  }
  std::uint64_t pairs() const { return rows_.pairs(); }

  // Each point sums its contacts in its partners' order, then adds the sum to its force: no
  // atomics, the same sums whatever the thread count. The law is evaluated as the link (a in A,
  // b in B) evaluates it, so each pair's force is the conditional link's to the bit.
  void apply(const Vec3* x, const Vec3* v, Vec3* f, int threads) const {
    const auto n = static_cast<std::int64_t>(near_.size());
    const Real k = spec_.stiffness, z = spec_.damping, s = spec_.threshold, l0 = spec_.rest_length;
    const auto one = [&](std::int64_t a) {
      const std::size_t qa = std::size_t(a);
      if (rows_.start[qa] == rows_.start[qa + 1]) return;
      const std::uint32_t pa = set_[near_[qa]];
      const bool b_side = (qtag_[qa] & kSideB) != 0;
      Vec3 sum{};
      for (std::uint32_t e = rows_.start[qa]; e < rows_.start[qa + 1]; ++e) {
        const std::uint32_t pb = set_[near_[rows_.partners[e]]];
        if (b_side)
          sum -= law::conditional_law(x[pb], x[pa], v[pb], v[pa], k, z, s, l0);
        else
          sum += law::conditional_law(x[pa], x[pb], v[pa], v[pb], k, z, s, l0);
      }
      f[pa] += sum;
    };
    // One thread: no parallel construct (even `if (false)` starts a team: a futex call a step).
    if (threads <= 1) {
      for (std::int64_t a = 0; a < n; ++a) one(a);
      return;
    }
#pragma omp parallel for schedule(static) num_threads(threads)
    for (std::int64_t a = 0; a < n; ++a) one(a);
  }

  // Every pair of the rows once, as (A's point, B's point).
  template <class F>
  void for_each_pair(F&& fn) const {
    for (std::uint32_t a = 0; a + 1 < rows_.start.size(); ++a)
      if (!(qtag_[a] & kSideB))
        for (std::uint32_t e = rows_.start[a]; e < rows_.start[a + 1]; ++e)
          fn(set_[near_[a]], set_[near_[rows_.partners[e]]]);
  }

 private:
  collision::Box grown_bounds(const Vec3* x, std::size_t begin, std::size_t end, Real r) const {
    if (begin == end) {  // an empty group: a box that holds nothing
      const Real big = std::numeric_limits<Real>::max();
      return {{big, big, big}, {-big, -big, -big}};
    }
    Vec3 lo = x[set_[begin]], hi = lo;
    for (std::size_t k = begin + 1; k < end; ++k) {
      const Vec3& p = x[set_[k]];
      lo = {std::min(lo.x, p.x), std::min(lo.y, p.y), std::min(lo.z, p.z)};
      hi = {std::max(hi.x, p.x), std::max(hi.y, p.y), std::max(hi.z, p.z)};
    }
    const Vec3 g{r, r, r};
    return {lo - g, hi + g};
  }
  static bool inside(const collision::Box& b, const Vec3& p) {
    return p.x >= b.lo.x && p.x <= b.hi.x && p.y >= b.lo.y && p.y <= b.hi.y && p.z >= b.lo.z &&
           p.z <= b.hi.z;
  }

  GroupContactSpec spec_;
  std::vector<std::uint32_t> set_;         // global ids: A's points, then B's
  std::vector<std::uint8_t> tag_;          // per local point: side (bit 0), fixed (bit 1)
  bool free_partner_[2] = {false, false};  // side 0 (A) / 1 (B): the other side has a free point
  std::size_t first_b_ = 0;                // B's points start here in set_
  std::vector<std::uint32_t> near_;        // this query's points (indices into set_, increasing)
  std::vector<Vec3> xs_;                   // their positions
  std::vector<std::uint8_t> qtag_;         // their tags
  collision::UniformGrid grid_;
  std::vector<collision::Sink> sinks_;
  collision::PartnerRows rows_;  // close partners per point
};

class GroupContactStage final : public Stage {
 public:
  GroupContactStage(const Model& m, std::vector<GroupContactSpec> specs)
      : specs_(std::move(specs)) {
    build(m);
  }
  std::string name() const override { return std::string(kGroupContactStage.name); }
  std::string refusal_hint() const override {
    return " (or give its [[contact]] tables method = \"links\": one conditional link per pair, "
           "which the GPU runs)";
  }
  Phase phase() const override { return kGroupContactStage.phase; }
  void model_changed(const Model& m) override { build(m); }

  void apply(const Model&, State& s, const StageContext& ctx) override {
    const Vec3* x = s.x().data();
    const Vec3* v = s.v().data();
    threads_ = ctx.threads;
    std::uint64_t active = 0, tested = 0;
    for (auto& c : contacts_) {
      tested += c.find(x, c.spec().threshold, ctx.threads);
      c.apply(x, v, s.f().data(), ctx.threads);
      active += c.pairs();
    }
    count(ctx, active, tested);
  }

  // Implicit schemes: the pairs within the threshold plus the step's motion margin, once, as
  // conditional links of the same law (no explicit pass); `active`: those acting at x_n.
  ContactKinds contacts_found() const override { return ContactKinds::pairs; }
  void find_contacts(const Model&, State& s, const StageContext& ctx, ContactSet& set) override {
    threads_ = ctx.threads;
    const std::uint64_t tested = contacts_as_links(s, Real(ctx.h), ctx.threads);
    set.add(links_);
    const Vec3* x = s.x().data();
    std::uint64_t active = 0;
    const auto params = links_.slot_params();
    const auto ends = links_.slot_ends();
    for (std::size_t l = 0; l < ends.size(); ++l)
      if (norm2(x[ends[l].b] - x[ends[l].a]) < params[l].threshold * params[l].threshold) ++active;
    count(ctx, active, tested);
  }

  void count(const StageContext& ctx, std::uint64_t active, std::uint64_t tested) {
    if (!ctx.profile) return;
    Profile& p = *ctx.profile;
    columns_.add(p, 0, active);
    columns_.count(p, 1, tested);
  }

  // The pairs within the threshold at s, each the conditional spring's energy (the links'
  // law: method = "links" stores the same springs and reports the same energy).
  double energy(const Model&, const State& s) override {
    const Vec3* x = s.x().data();
    double e = 0;
    for (auto& c : contacts_) {
      const GroupContactSpec& sp = c.spec();
      const ConditionalSpringDamper::Params p{sp.stiffness, sp.damping, sp.threshold,
                                              sp.rest_length};
      c.find(x, sp.threshold, threads_);  // the last pass's threads: lists keep their size
      c.for_each_pair([&](std::uint32_t a, std::uint32_t b) {
        e += ConditionalSpringDamper::energy(x[a], x[b], p);
      });
    }
    return e;
  }

  // As the conditional links' pool bounds them: at most 4 partners at once per point, each as
  // stiff as the stiffest contact the point takes part in (counted twice when the partner may
  // be free: Gershgorin).
  void stability_terms(std::span<const Real>, std::span<Real> k_row,
                       std::span<Real> c_row) const override {
    std::vector<Real> k_max(k_row.size(), 0), c_max(k_row.size(), 0);
    for (const auto& c : contacts_)
      for (std::size_t l = 0; l < c.set().size(); ++l) {
        const std::uint32_t p = c.set()[l];
        const Real w = c.partner_may_be_free(l) ? 2 : 1;
        k_max[p] = std::max(k_max[p], w * c.spec().stiffness);
        c_max[p] = std::max(c_max[p], w * c.spec().damping);
      }
    for (std::size_t i = 0; i < k_row.size(); ++i) {
      k_row[i] += LinkPool<ConditionalSpringDamper>::kSimultaneousContacts * k_max[i];
      c_row[i] += LinkPool<ConditionalSpringDamper>::kSimultaneousContacts * c_max[i];
    }
  }

  std::vector<StageOption> options() const override {
    return {{"draw_contacts", {"on", "off"}, draw_contacts_ ? "on" : "off"}};
  }
  void set_option(const std::string& name, const std::string& value) override {
    if (name != "draw_contacts") return Stage::set_option(name, value);
    if (value != "on" && value != "off")
      throw std::invalid_argument(std::string(kGroupContactStage.name) +
                                  ": option draw_contacts cannot be '" + value + "'");
    draw_contacts_ = value == "on";
  }

  // This step's contacts, in green (the viewer's overlay), when draw_contacts is on.
  void overlay(const Model&, const State& s, std::vector<OverlaySegment>& out) const override {
    if (!draw_contacts_) return;
    const Vec3* x = s.x().data();
    for (const auto& c : contacts_)
      c.for_each_pair([&](std::uint32_t a, std::uint32_t b) {
        out.push_back({x[a], x[b], {0.2f, 1.0f, 0.3f}});
      });
  }

 private:
  void build(const Model& m) {
    contacts_.clear();
    for (const auto& spec : specs_) contacts_.emplace_back(m, spec);
  }

  // For implicit schemes: the pairs within the threshold plus the step's motion margin as
  // conditional links (the same law), so that a solve that moves points by a whole step still
  // sees every pair that comes within the threshold. The margin is the self-collision stage's:
  // h times 2.5 the largest speed relative to the points' mean velocity, at least a quarter of
  // the threshold.
  std::uint64_t contacts_as_links(const State& s, Real h, int threads) {
    std::uint64_t tested = 0;
    links_.clear();
    const auto v = s.v();
    for (auto& c : contacts_) {
      const GroupContactSpec& sp = c.spec();
      const Real margin = std::max(collision::motion_margin(v.data(), c.set(), h),
                                   collision::kMinMarginFraction * sp.threshold);
      tested += c.find(s.x().data(), sp.threshold + margin, threads);
      c.for_each_pair([&](std::uint32_t a, std::uint32_t b) {
        links_.add({a, b}, {sp.stiffness, sp.damping, sp.threshold, sp.rest_length});
      });
    }
    links_.prepare(std::uint32_t(s.size()));
    return tested;
  }

  std::vector<GroupContactSpec> specs_;
  std::vector<GroupContact> contacts_;
  LinkPool<ConditionalSpringDamper> links_;  // implicit schemes: this step's candidates
  ProfileColumns columns_{{"active_conditional_links"}, {"group_contact_candidates"}};
  bool draw_contacts_ = false;
  int threads_ = 1;  // of the last apply()
};

}  // namespace

std::unique_ptr<Stage> make_group_contact_stage(const Model& m,
                                                const std::vector<GroupContactSpec>& specs) {
  return std::make_unique<GroupContactStage>(m, specs);
}

}  // namespace maille
