// The facet obstacle stage: inverse dynamics on a triangle mesh (include/maille/obstacle.hpp).
//
// Per colliding particle, once per step after every force (Phase::response):
//   1. the segment P -> Q it will travel (Q = P + h V, or P + h (V + h F / m) for schemes that
//      kick before they drift: the ray, made exact for the scheme) goes into the mesh's
//      frame, P through the placement at t and Q through the placement at t + h, so a moving
//      obstacle is met by the relative motion;
//   2. the grid gives the nearby facets; the ray-facet test picks the earliest crossing; the
//      response rewrites F and V (facet_response.hpp) and the new segment is tested again, up to
//      kPasses times (a particle driven into a concave corner meets both faces);
//   3. no crossing, but resting on a facet (|N.AP| <= eps, test (a) fails) and
//      heading into it: the same response, so a resting particle is held (on a static surface
//      with no facet above its plane, the most common contact, at the end of its block of
//      particles, with the block's other such responses);
//   4. a closed mesh: a particle found behind its closest facet (by pseudo-normals) is inside:
//      it is put back on the surface, its inward velocity removed, and counted in facet_leaks.
#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <limits>
#include <stdexcept>

#ifdef _OPENMP
#include <omp.h>
#endif

#include "../thread_lists.hpp"
#include "facet_grid.hpp"
#include "facet_response.hpp"
#include "maille/obstacle.hpp"
#include "maille/profile.hpp"
#include "maille/state.hpp"
#include "obstacle_surface.hpp"

namespace maille {

namespace {

constexpr int kPasses = 4;
// Particles per block of the stage's loop (the resting contacts they find, at most one each,
// are answered at the end of the block).
constexpr std::int64_t kBlock = 256;
// Nearby facets whose N.AP the first pass keeps for the next ones (more: recomputed).
constexpr std::size_t kKeptAbove = 64;
// A facet more than the segment's length above p cannot be crossed by it (reach(), below).
constexpr Real kReachMargin = Real(1) + Real(1e-7);

struct Counts {
  std::uint64_t contacts = 0, hits = 0, sticks = 0, slides = 0, leaks = 0;
  Real deepest = 0;
  // A particle's contact this step, whether it ends stuck or sliding.
  void contact(bool stuck) {
    ++contacts;
    stuck ? ++sticks : ++slides;
  }
  void add(const Counts& o) {
    contacts += o.contacts, hits += o.hits, sticks += o.sticks, slides += o.slides;
    leaks += o.leaks;
    deepest = std::max(deepest, o.deepest);
  }
};

Vec3 lower(const Vec3& a, const Vec3& b) {
  return {std::min(a.x, b.x), std::min(a.y, b.y), std::min(a.z, b.z)};
}
Vec3 upper(const Vec3& a, const Vec3& b) {
  return {std::max(a.x, b.x), std::max(a.y, b.y), std::max(a.z, b.z)};
}

// A static obstacle's mesh placed in the world once: its particles then need no transform.
TriMesh placed(const TriMesh& mesh, const shapes::Affine& a) {
  TriMesh out = mesh;
  for (Vec3& v : out.vertices) v = a.to_world(v);
  return out;
}

// Largest stretch of a matrix (its Frobenius norm bounds the largest singular value).
Real stretch_bound(const Mat3& m) {
  Real s = 0;
  for (const auto& row : m.m)
    for (Real e : row) s += e * e;
  return std::sqrt(s);
}

class FacetObstacleStage final : public Stage {
 public:
  FacetObstacleStage(const Model& m, Obstacle o)
      : o_(std::move(o)),
        set_(colliding_points(m, o_)),
        row_(set_.size()),
        clearance_(set_.size()),
        surface_(o_, std::make_shared<const TriMesh>(obstacle_mesh(o_))),
        world_(!o_.motion.moves()),
        grid_(world_ ? placed(*surface_.mesh(), o_.place) : *surface_.mesh()) {
    if (grid_.facets().empty())
      throw std::invalid_argument("obstacle '" + o_.name + "': the mesh has no facet");
    // The tolerance eps in each facet's own units: a world distance d along the facet's world
    // normal is d |M_i^T n| in the mesh frame (a rigid motion on top does not change it).
    terms_.reserve(grid_.facets().size());
    for (std::uint32_t fi = 0; fi < grid_.facets().size(); ++fi) {
      const auto [n, stretch] = world_normal(world_ ? shapes::Affine{} : o_.place, fi);
      terms_.push_back({n, o_.epsilon * stretch});
      widest_eps_ = std::max(widest_eps_, terms_.back().eps);
    }
    // Rounding of N.AP (a difference, then a dot product) in this frame: a few units of
    // 2^-53 of |P| + |A|, both within the grid's box; 1e-12 of its size is generous.
    const Vec3 lo = grid_.lo(), hi = grid_.hi();
    const Vec3 corner{std::max(std::abs(lo.x), std::abs(hi.x)),
                      std::max(std::abs(lo.y), std::abs(hi.y)),
                      std::max(std::abs(lo.z), std::abs(hi.z))};
    rounding_ = Real(1e-12) * (norm(corner) + std::numeric_limits<Real>::min());
  }

  std::string name() const override { return obstacle_stage_name(o_); }
  Phase phase() const override { return obstacle_phase(o_.method); }

  void apply(const Model& m, State& s, const StageContext& ctx) override {
    const Real h = Real(ctx.h);
    const shapes::Affine now = frame_at(ctx.t);
    const shapes::Affine next = frame_at(ctx.t + ctx.h);
    // Distances in the mesh frame are world distances times |M_i^T n| (per facet); the query
    // box is grown by eps times the largest stretch so it holds every facet within eps.
    const Step step{ctx, h, now, next, 2 * o_.epsilon * stretch_bound(now.inverse)};
    const int threads = std::max(1, ctx.threads);
    if (scratch_.size() < std::size_t(threads)) scratch_.resize(threads);
    counts_.assign(threads, Counts{});
    // Whether the sweep was made lives in the State (a checkpoint resumed by a fresh stage must
    // not sweep again): the number of particles it covered, so a model change that changes the
    // colliding set sweeps anew.
    std::vector<double>& swept = s.memory(name());
    if (swept.size() != 1 || swept[0] != double(set_.size())) {
      sweep_inside(s, now, counts_[0]);
      swept.assign(1, double(set_.size()));
    }
    auto& counts = counts_;
    const auto n = static_cast<std::int64_t>(set_.size());
    Vec3* x = s.x().data();
    Vec3* v = s.v().data();
    Vec3* f = s.f().data();
    const Real* inv_mass = m.points.inv_mass.data();
    if (resting_.size() < std::size_t(threads)) resting_.resize(threads);
    // In blocks: the particles' tests first, then the responses of the resting contacts they
    // found (Resting), in one loop.
    const std::int64_t blocks = (n + kBlock - 1) / kBlock;
#pragma omp parallel for schedule(dynamic, 1) num_threads(threads) if (threads > 1)
    for (std::int64_t b = 0; b < blocks; ++b) {
      const int t = threads > 1 ? thread_index() : 0;
      Resting& resting = resting_[t];
      resting.count = 0;
      for (std::int64_t i = b * kBlock, end = std::min(n, (b + 1) * kBlock); i < end; ++i) {
        const std::uint32_t p = set_[i];
        particle(p, x[p], v[p], f[p], inv_mass[p], step, scratch_[t], row_[i], clearance_[i],
                 resting, counts[t]);
      }
      respond_resting(resting, v, f, inv_mass, step, counts[t]);
    }
    collision::room_for_any_item(scratch_);  // whichever thread meets the busiest particle next
    Counts total;
    for (const Counts& c : counts) total.add(c);
    report(ctx, total);
  }

  // No stability_terms: the response is no stiffness the explicit limit must allow for.

  void surfaces(double t, std::vector<SurfaceInstance>& out) const override {
    surface_.add(o_, t, out);
  }

 private:
  // Where the grid's frame is at time t: the world itself for a static obstacle (its mesh was
  // placed once), else the placement moved by the motion (particles go into the mesh's frame).
  shapes::Affine frame_at(double t) const {
    return world_ ? shapes::Affine{} : o_.motion.at(o_.place, t);
  }
  Vec3 to_frame(const shapes::Affine& a, const Vec3& x) const {
    return world_ ? x : a.to_canonical(x);
  }

  static int thread_index() {
#ifdef _OPENMP
    return omp_get_thread_num();
#else
    return 0;
#endif
  }

  // World normal of facet fi at the placement `now`: the one at rest turned by the motion's
  // rotation (the rigid motion keeps normals unit: no square root per contact).
  Vec3 normal_at(const shapes::Affine& now, std::uint32_t fi) const {
    if (!o_.motion.moves()) return terms_[fi].normal;
    return now.direct * (o_.place.inverse * terms_[fi].normal);
  }

  // World normal of facet fi under placement a, and the factor from world to mesh-frame
  // distances along it.
  std::pair<Vec3, Real> world_normal(const shapes::Affine& a, std::uint32_t fi) const {
    const Vec3 w = transpose_times(a.inverse, grid_.facets()[fi].n);
    const Real l = norm(w);
    return {l > 0 ? w / l : Vec3{0, 1, 0}, l};
  }

  // Per colliding particle, a lower bound on N.AP of every facet of its row's cell, valid at
  // `anchor` (its N.AP found there by the first scan, less their rounding). N.AP moves no more
  // than P does (N unit), so at P, N.AP >= below - |P - anchor| for each facet. When that bound
  // exceeds eps (the widest) and the segment's reach, every facet is above P beyond eps (no
  // resting contact, nothing behind) and out of reach (no crossing): the scan would find
  // nothing, so it is skipped. A particle hovering near the mesh (about half of those near it on
  // the draped cloth of the benchmark) then costs its query and this test; one touching a
  // facet is scanned every step, as before. Reset when the query falls in another cell.
  struct Clearance {
    Vec3 anchor;
    Real below = -std::numeric_limits<Real>::infinity();
    bool out_of_reach(const Vec3& p, const Vec3& q, Real eps) const {
      // |P - anchor| bounded above by the sum of its coordinates' magnitudes (no square root on
      // this path, which most particles near the mesh take), rounded up by far more than its
      // rounding; squares compared for the reach (reach2 carries the scan's margin), so a NaN
      // anywhere keeps the scan.
      const Vec3 d = p - anchor;
      const Real moved = (std::abs(d.x) + std::abs(d.y) + std::abs(d.z)) * (1 + Real(1e-12));
      const Real clear = below - moved;
      return clear > eps && clear * clear > reach2(p, q);
    }
  };

  // The resting contacts a block of particles found: (point, facet) pairs answered in one loop
  // after the block's tests (respond_resting), where consecutive responses, independent of one
  // another, overlap their square roots and divisions instead of waiting on each in turn.
  struct Resting {
    std::array<std::uint32_t, kBlock> point, facet;
    std::size_t count = 0;
    void add(std::uint32_t p, std::uint32_t fi) {
      point[count] = p, facet[count] = fi;
      ++count;
    }
  };

  struct Contact {
    bool found = false;
    bool swept = false;   // the ray's crossing (else: resting on the facet)
    bool behind = false;  // p is behind a nearby facet it projects onto: maybe inside
    std::uint32_t facet = 0;
  };

  // The first pass's N.AP of the nearby facets, for the next passes (p does not move between
  // them): only facets above their plane (N.AP > eps) can be crossed, and the next passes test
  // only those of them the new segment can reach, with no facet record read for the others.
  struct Seen {
    bool kept = false;       // the near facets fit: above and over hold them all
    std::uint64_t over = 0;  // bit k: N.AP > eps for the k-th near facet
    Real lowest = 0;         // the least N.AP (NaN if any is; -inf when they are not kept)
    std::array<Real, kKeptAbove> above;  // N.AP per near facet
  };

  // The square of the distance beyond which a facet's plane is out of the segment's reach:
  // facet f can be crossed only if N.AP <= -N.PQ <= |PQ| (N unit), so N.AP^2 > |PQ|^2 rules
  // it out. The margin (1e-7) covers the rounding of the unit normal and of the products, so
  // a facet ruled out is one the exact ray-facet test would reject (u > 1): skipping it changes
  // no result, it only saves the division and the inside test. A NaN or infinite reach rules
  // nothing out.
  static Real reach2(const Vec3& p, const Vec3& q) {
    return norm2(q - p) * kReachMargin;
  }
  static bool out_of_reach(Real above, Real reach2) {
    return above * above > reach2;
  }

  // What every particle of a step shares.
  struct Step {
    const StageContext& ctx;
    Real h;
    const shapes::Affine& now;   // the grid's frame at t
    const shapes::Affine& next;  // and at t + h
    Real band;                   // the query box's growth: it holds every facet within eps
  };

  // Where the particle ends this step as it moves now, in the grid's frame at t + h.
  Vec3 end_point(const Vec3& x, const Vec3& v, const Vec3& f, Real inv_mass, const Step& s) const {
    const Vec3 kicked = s.ctx.drift_after_kick ? v + f * (s.h * inv_mass) : v;
    return to_frame(s.next, x + kicked * s.h);
  }

  // One particle: the query and the clearance test, which settle most particles of a draped
  // cloth (far from the mesh, or hovering over it), stay small enough to be inlined in the
  // loop; the others go to collide().
  void particle(std::uint32_t point, Vec3& x, Vec3& v, Vec3& f, Real inv_mass, const Step& s,
                std::vector<std::uint32_t>& scratch, facets::FacetGrid::Row& row, Clearance& clear,
                Resting& resting, Counts& c) const {
    const Vec3 p = to_frame(s.now, x);
    const Vec3 q = end_point(x, v, f, inv_mass, s);
    const std::uint64_t cell = row.cell;
    const Vec3 band = Vec3{1, 1, 1} * s.band;
    const std::span<const std::uint32_t> near =
        grid_.candidates(lower(p, q) - band, upper(p, q) + band, scratch, row);
    if (near.empty()) return;  // far from the obstacle: one box test
    if (row.cell != cell) clear.below = -std::numeric_limits<Real>::infinity();  // other facets
    if (row.in_cell && clear.out_of_reach(p, q, widest_eps_)) return;  // clear of every facet
    collide(point, x, v, f, inv_mass, s, p, q, near, row.in_cell, clear, resting, c);
  }

  // The ray-facet test and response for a particle near facets (`near`), from p to q. Kept out of
  // line: its frame (the first pass's records, the response) would otherwise be set up for
  // every particle, most of which never come here.
  [[gnu::noinline]] void collide(std::uint32_t point, Vec3& x, Vec3& v, Vec3& f, Real inv_mass,
                                 const Step& s, const Vec3& p, Vec3 q,
                                 std::span<const std::uint32_t> near, bool in_cell,
                                 Clearance& clear, Resting& resting, Counts& c) const {
    const StageContext& ctx = s.ctx;
    const shapes::Affine& now = s.now;
    const Vec3 surface_v = o_.motion.moves() ? o_.motion.velocity_at(x, ctx.t) : Vec3{};
    bool touched = false, stuck = false, behind = false;
    // What the first pass learns of the nearby facets, kept for the next ones.
    Seen seen;
    for (int pass = 0; pass < kPasses; ++pass) {
      const Contact hit =
          pass == 0 ? first_contact(p, q, near, seen) : next_contact(p, q, near, seen);
      if (pass == 0 && in_cell) clear = {p, seen.lowest - rounding_};
      behind |= hit.behind;
      if (!hit.found) break;
      // The most common contact, a particle resting on a static surface with no facet above
      // its plane: its response is the last thing this step does to it (no later pass, no
      // inside check), so it is left to respond_resting, with the block's others.
      if (pass == 0 && !hit.swept && seen.kept && seen.over == 0 && !behind && !o_.motion.moves()) {
        resting.add(point, hit.facet);
        return;
      }
      c.hits += pass == 0 && hit.swept;
      touched = true;
      stuck = facets::respond(v, f, normal_at(now, hit.facet), surface_v, inv_mass, s.h, o_.alpha,
                              o_.beta, ctx.drift_after_kick)
                  .stuck;
      q = end_point(x, v, f, inv_mass, s);
      if (q == p) break;  // held still (a resting, sticking particle): nothing left to cross
      // No facet above its plane (a resting particle, most often): p does not move, so no
      // later pass can find a crossing; the scan would say so after a call.
      if (seen.kept && seen.over == 0) break;
      if (pass == kPasses - 1 && next_contact(p, q, near, seen).found) {
        v = surface_v;  // cornered: stay where it is (outside) for this step
        f = {};
      }
    }
    if (touched) c.contact(stuck);
    if (behind && grid_.closed()) push_out_if_inside(p, x, v, f, surface_v, now, near, c);
  }

  // The responses of a block's resting contacts (collide: a static surface, the first pass),
  // counted as collide counts them.
  void respond_resting(const Resting& resting, Vec3* v, Vec3* f, const Real* inv_mass,
                       const Step& s, Counts& c) const {
    for (std::size_t k = 0; k < resting.count; ++k) {
      const std::uint32_t p = resting.point[k];
      c.contact(facets::respond(v[p], f[p], normal_at(s.now, resting.facet[k]), Vec3{}, inv_mass[p],
                                s.h, o_.alpha, o_.beta, s.ctx.drift_after_kick)
                    .stuck);
    }
  }

  // The first scan of the nearby facets: the earliest one the segment p -> q crosses (ties:
  // the lowest index); else a facet the particle rests on: within eps of its plane, over it,
  // heading into it (test (a) fails there, yet it must be held). It also notes
  // whether p lies behind a facet it projects onto, the only way a particle can be inside a
  // closed mesh near its surface (most are not: no closest-point search for them), and fills
  // `seen` for the next passes. One loop with no branch sorts the facets into bit masks (within
  // reach above the plane, within eps of it) and the nearest plane; the exact tests then run
  // on the few flagged facets, in the order of `near` (so ties resolve as before).
  Contact first_contact(const Vec3& p, const Vec3& q, std::span<const std::uint32_t> near,
                        Seen& seen) const {
    const Real reach = reach2(p, q);
    seen.kept = near.size() <= seen.above.size();
    seen.lowest = -std::numeric_limits<Real>::infinity();
    if (!seen.kept) return first_contact_any(p, q, near, reach);
    Real lowest = std::numeric_limits<Real>::infinity();
    std::uint64_t over = 0, crossing = 0, resting = 0;
    // The facet whose plane is nearest p: a particle inside a closed mesh, near its surface,
    // lies behind it and over it (one inside test per particle, not one per facet).
    Real nearest = std::numeric_limits<Real>::max(), nearest_above = 0;
    std::uint32_t nearest_facet = 0;
    for (std::size_t k = 0; k < near.size(); ++k) {
      const std::uint32_t fi = near[k];
      const facets::Facet& fa = grid_.facets()[fi];
      const Real above = dot(fa.n, p - fa.a), eps = terms_[fi].eps;
      seen.above[k] = above;
      lowest = above >= lowest ? lowest : above;  // a NaN sticks: no clearance then
      const bool is_over = above > eps;
      over |= std::uint64_t(is_over) << k;
      crossing |= std::uint64_t(is_over & !out_of_reach(above, reach)) << k;
      resting |= std::uint64_t(!is_over & (above >= -eps)) << k;
      const Real distance = std::abs(above);
      const bool closer = distance < nearest;
      nearest = closer ? distance : nearest;
      nearest_above = closer ? above : nearest_above;
      nearest_facet = closer ? fi : nearest_facet;
    }
    seen.over = over, seen.lowest = lowest;
    Contact hit;
    Real first = 2;
    for (; crossing != 0; crossing &= crossing - 1) {
      const auto k = static_cast<std::size_t>(std::countr_zero(crossing));
      const std::uint32_t fi = near[k];
      Real u;
      if (grid_.crosses_above(fi, seen.above[k], p, q, terms_[fi].eps, u) &&
          (u < first || (u == first && fi < hit.facet)))
        first = u, hit = {true, true, false, fi};
    }
    if (nearest_above < -terms_[nearest_facet].eps)
      hit.behind = grid_.projects_inside(nearest_facet, p);
    if (hit.found) return hit;
    Contact rest;
    const Vec3 pq = q - p;
    for (; resting != 0; resting &= resting - 1) {
      const std::uint32_t fi = near[static_cast<std::size_t>(std::countr_zero(resting))];
      if ((!rest.found || fi < rest.facet) && dot(grid_.facets()[fi].n, pq) < 0 &&
          grid_.projects_inside(fi, p))
        rest = {true, false, hit.behind, fi};
    }
    return rest.found ? rest : hit;
  }

  // The same, one facet at a time, for more nearby facets than `seen` holds (a fast particle's
  // query over many cells).
  Contact first_contact_any(const Vec3& p, const Vec3& q, std::span<const std::uint32_t> near,
                            Real reach) const {
    Contact hit, rest;
    Real first = 2;
    Real nearest = std::numeric_limits<Real>::max(), nearest_above = 0;
    std::uint32_t nearest_facet = 0;
    for (const std::uint32_t fi : near) {
      const facets::Facet& fa = grid_.facets()[fi];
      const Real above = dot(fa.n, p - fa.a), eps = terms_[fi].eps;
      Real u;
      if (above > eps) {
        if (!out_of_reach(above, reach) && grid_.crosses_above(fi, above, p, q, eps, u) &&
            (u < first || (u == first && fi < hit.facet)))
          first = u, hit = {true, true, false, fi};
      } else if (above >= -eps) {
        if ((!rest.found || fi < rest.facet) && dot(fa.n, q - p) < 0 &&
            grid_.projects_inside(fi, p))
          rest = {true, false, false, fi};
      }
      if (std::abs(above) < nearest)
        nearest = std::abs(above), nearest_above = above, nearest_facet = fi;
    }
    if (nearest_above < -terms_[nearest_facet].eps)
      hit.behind = grid_.projects_inside(nearest_facet, p);
    if (!hit.found && rest.found) rest.behind = hit.behind, hit = rest;
    return hit;
  }

  // A later scan, after a response changed q (p is the same): the earliest crossing only.
  Contact next_contact(const Vec3& p, const Vec3& q, std::span<const std::uint32_t> near,
                       const Seen& seen) const {
    const Real reach = reach2(p, q);
    Contact hit;
    Real first = 2;
    auto test = [&](std::uint32_t fi, Real above) {
      Real u;
      if (!out_of_reach(above, reach) && grid_.crosses_above(fi, above, p, q, terms_[fi].eps, u) &&
          (u < first || (u == first && fi < hit.facet)))
        first = u, hit = {true, true, false, fi};
    };
    if (seen.kept) {
      // Only the facets above their plane, no facet record read for those out of reach.
      for (std::uint64_t over = seen.over; over != 0; over &= over - 1) {
        const auto k = static_cast<std::size_t>(std::countr_zero(over));
        test(near[k], seen.above[k]);
      }
    } else {
      for (const std::uint32_t fi : near) {
        const facets::Facet& fa = grid_.facets()[fi];
        const Real above = dot(fa.n, p - fa.a);
        if (above > terms_[fi].eps) test(fi, above);
      }
    }
    return hit;
  }

  void model_changed(const Model& m) override {
    set_ = colliding_points(m, o_);
    row_.assign(set_.size(), {});
    clearance_.assign(set_.size(), {});
  }

  // Once, before the first step (and after a model change): a particle may start inside a
  // closed mesh (a scene that overlaps it), deeper than the per-step check looks. Each particle
  // in the mesh's box gets the exact test (nearest facet, pseudo-normal sign) and is put out.
  void sweep_inside(State& s, const shapes::Affine& now, Counts& c) {
    if (!grid_.closed()) return;
    for (std::uint32_t p : set_) {
      const Vec3 local = to_frame(now, s.x()[p]);
      if (!grid_.inside_box(local)) continue;
      const facets::Closest cl = grid_.nearest(local);
      if (cl.sign < 0) put_out(cl, s.x()[p], s.v()[p], s.f()[p], {}, now, c);
    }
  }

  void push_out_if_inside(const Vec3& p, Vec3& x, Vec3& v, Vec3& f, const Vec3& surface_v,
                          const shapes::Affine& now, std::span<const std::uint32_t> near,
                          Counts& c) const {
    facets::Closest best;
    best.distance2 = std::numeric_limits<Real>::max();
    for (std::uint32_t fi : near) {
      const facets::Closest cl = grid_.closest(fi, p);
      if (cl.distance2 < best.distance2) best = cl;
    }
    if (best.sign > 0) return;
    put_out(best, x, v, f, surface_v, now, c);
  }

  // A particle found inside: onto the surface (2 eps out along the facet's normal), its inward
  // relative velocity and force removed.
  void put_out(const facets::Closest& best, Vec3& x, Vec3& v, Vec3& f, const Vec3& surface_v,
               const shapes::Affine& now, Counts& c) const {
    const Vec3 n = normal_at(now, best.facet);
    const Vec3 surface = world_ ? best.point : now.to_world(best.point);
    c.deepest = std::max(c.deepest, norm(surface - x));
    x = surface + n * (2 * o_.epsilon);
    const Real vn = dot(v - surface_v, n);
    if (vn < 0) v -= n * vn;
    const Real fn = dot(f, n);
    if (fn < 0) f -= n * fn;
    ++c.leaks;
  }

  void report(const StageContext& ctx, const Counts& total) {
    if (!ctx.profile) return;
    Profile& pr = *ctx.profile;
    if (columns_.empty()) {
      const std::string base = "obstacle_" + o_.name + "_";
      columns_ = {{base + "contacts"}, {base + "depth", true}, {base + "hits"},
                  {base + "sticks"},   {base + "slides"},      {base + "facet_leaks"}};
    }
    columns_.set(
        pr, {total.contacts, total.deepest, total.hits, total.sticks, total.slides, total.leaks});
  }

  Obstacle o_;
  std::vector<std::uint32_t> set_;
  // Per colliding point: the grid cell of its last query and its facets (FacetGrid::Row).
  std::vector<facets::FacetGrid::Row> row_;
  std::vector<Clearance> clearance_;  // per colliding point: the scan it may skip
  ObstacleSurface surface_;
  bool world_;  // static: the grid holds the placed mesh, in the world's frame
  facets::FacetGrid grid_;
  // Per facet, beside the grid's record: what the scan reads of every facet (eps) and the
  // response of the one it meets (its world normal), in one cache line (aligned: never two).
  struct alignas(32) Terms {
    Vec3 normal;  // in the world at rest (placement `place`)
    Real eps;     // the facet tolerance eps, in the mesh frame
  };
  std::vector<Terms> terms_;
  Real widest_eps_ = 0;  // the largest of them
  Real rounding_ = 0;    // bound on the rounding of a facet's N.AP (Clearance)
  std::vector<std::vector<std::uint32_t>> scratch_;  // per thread: nearby facets
  std::vector<Counts> counts_;                       // per thread
  std::vector<Resting> resting_;                     // per thread: its block's resting contacts
  ProfileColumns columns_;
};

}  // namespace

std::unique_ptr<Stage> make_facet_obstacle_stage(const Model& m, const Obstacle& o) {
  return std::make_unique<FacetObstacleStage>(m, o);
}

}  // namespace maille
