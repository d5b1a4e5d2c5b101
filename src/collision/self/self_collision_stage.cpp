// The self-collision stage: the engine (self_collision_engine.hpp) in the simulator's step: the
// explicit pass and its displacement bounds, the implicit schemes' contact set and its searches
// again, counters, live options, the intersection check; and the stage's factory.
#include "maille/self_collision.hpp"

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
#include "maille/shared_laws.hpp"
#include "maille/simulator.hpp"
#include "maille/state.hpp"
#include "self_collision_engine.hpp"
#include "self_collision_view.hpp"
#include "self_contact_link.hpp"
#include "triangle_contact_terms.hpp"
#include "triangle_proximity.hpp"

namespace maille {

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
    take_members(m);
  }
  std::string name() const override { return std::string(kSelfCollisionStage.name); }
  std::string refusal_hint() const override { return " (or without it: --no-self-collision)"; }
  Phase phase() const override { return kSelfCollisionStage.phase; }
  void model_changed(const Model& m) override {
    engine_.release_exclusion();
    wide_.reset();
    engine_ = SelfCollision(m, settings_);
    warnings_ = leak_warnings(m, engine_.settings());
    anchored_ = anchored_triangles(m);
    faces_ = group_faces(m, settings_.groups);
    take_members(m);
    last_cell_ = 0;
  }
  // The points a solver's drift guard watches: the colliding particles, the fixed or driven
  // corners of the faces and, with triangles, the groups' other fixed or driven points, which
  // probe the faces (they do not move inside a solve; the common displacement must suit them
  // too).
  void take_members(const Model& m) {
    members_ = engine_.set();
    for (const auto& f : faces_) members_.insert(members_.end(), f.begin(), f.end());
    if (engine_.settings().primitive == Primitive::triangles) {
      const std::vector<std::uint8_t> in = group_mask(m, engine_.settings().groups);
      for (std::uint32_t p = 0; p < m.points.size(); ++p)
        if (in[p] && !(m.points.inv_mass[p] > 0)) members_.push_back(p);
    }
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
    clamp_columns_.count(profile, 1, bounded_ ? 0 : 1);
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
    clamp_columns_.count(profile, 0, clamped);
    return clamped;
  }

  // Implicit schemes: this step's candidates within s + margin, once (no explicit pass); the
  // counters give the candidates and those acting at x_n.
  ContactKinds contacts_found() const override {
    return engine_.settings().primitive == Primitive::triangles
               ? ContactKinds::pairs | ContactKinds::stencils
               : ContactKinds::pairs;
  }
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
  // same arrays (the friction's lag taken there too), each pair's margin from the iterate's
  // motion since x_n within the step's wide margin (contacts_as_links, `again`); or, with
  // `moved`, the stencil candidates of those points added (search_near).
  bool find_contacts_again(const Model& m, State& s, const StageContext& ctx,
                           std::span<const std::uint32_t> moved) override {
    if (!enabled_ || engine_.settings().primitive != Primitive::triangles) return false;
    if (!moved.empty()) {
      search_near(s, ctx, moved);
    } else {
      contacts_.clear();
      triangle_terms_.storage().clear();
      triangle_terms_.set_edge_begin(0);
      contacts_as_links(m, s, ctx, true);
    }
    ++searches_;
    count_searches(ctx);
    return true;
  }

  // The stencil candidates of the moved points within s + 4 L at the iterate (L the drift
  // limit), added to the step's. A moved point's new ball (radius L about where it is) and any
  // other point's (its first, which it may cross whole: 2 L) close a pair by at most 4 L, a
  // face or an edge moving no farther than its farthest corner: a pair left out stays farther
  // apart than s, the contact distance (docs/implicit.md). The point pairs are not guarded
  // (no drift limit) and stay as found.
  void search_near(State& s, const StageContext& ctx, std::span<const std::uint32_t> moved) {
    const Real radius = engine_.settings().radius;
    moved_mask_.resize(s.size(), 0);  // all zero between searches, a refusal's throw included
    for (const std::uint32_t p : moved) moved_mask_[p] = 1;
    struct Unmark {
      std::vector<std::uint8_t>& mask;
      std::span<const std::uint32_t> points;
      ~Unmark() {
        for (const std::uint32_t p : points) mask[p] = 0;
      }
    } unmark{moved_mask_, moved};
    std::size_t edge_begin =
        std::min(triangle_terms_.edge_begin(), triangle_terms_.storage().size());
    engine_.triangle_candidates_near(
        s.x().data(), moved_mask_.data(), radius + 4 * kDriftShare * radius, ctx.threads,
        triangle_terms_.storage(), edge_begin, triangle_terms_.edge_particles());
    triangle_terms_.set_edge_begin(edge_begin);
    // The friction's lag of every candidate at the iterate, as a search everywhere takes it
    // (the edge candidates' indices moved with the new point-face ones).
    triangle_terms_.lag(s.x().data(), s.v().data());
  }

  void count_searches(const StageContext& ctx) {
    if (!ctx.profile) return;
    if (searches_id_ < 0) searches_id_ = ctx.profile->counter("self_searches");
    ctx.profile->set_count(searches_id_, searches_);
  }

  void count(const StageContext& ctx, const SelfCollisionStats& st) {
    if (!ctx.profile) return;
    // The cost model P n^2 at the resolution used, beside the stage's measured time
    // (ns_self_collision) in every stats.csv row: P occupied cells, n particles per cell.
    const double per_cell =
        double(engine_.particles()) / std::max<double>(double(st.occupied_cells), 1);
    columns_.set(*ctx.profile, {st.candidate_pairs, st.contacts, st.occupied_cells, st.excluded,
                                st.skipped_cells, st.cell_size, st.triangle_contacts,
                                double(st.occupied_cells) * per_cell * per_cell, st.edge_contacts});
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
  ProfileColumns columns_{
      {"self_candidate_pairs"},   {"self_contacts"},        {"self_occupied_cells"},
      {"self_excluded_pairs"},    {"self_skipped_cells"},   {"self_cell_size", true},
      {"self_triangle_contacts"}, {"self_model_Pn2", true}, {"self_edge_contacts"}};
  ProfileColumns clamp_columns_{{"self_clamped_points"}, {"self_unbounded_steps"}};
  std::vector<Vec3> xn_;     // positions of the step's first force pass
  std::vector<Real> bound_;  // each point's displacement bound from xn_ (m)
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

  // Triangles with a fixed or driven corner, and fixed or driven points probing the faces, do
  // not follow the particles' common motion (a particle falling onto a pinned cloth, a cloth
  // falling onto a peg): speeds are then taken as they are.
  bool anchored_ = false;
  bool anchored_triangles(const Model& m) const {
    if (engine_.settings().primitive != Primitive::triangles) return false;
    const std::vector<std::uint8_t> in = group_mask(m, engine_.settings().groups);
    for (std::uint32_t p = 0; p < m.points.size(); ++p)
      if (in[p] && m.points.inv_mass[p] == 0) return true;  // a face's corner, or a probe
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
  std::vector<std::uint32_t> members_;    // take_members()
  std::vector<std::uint8_t> moved_mask_;  // search_near(): by global id
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

}  // namespace maille
