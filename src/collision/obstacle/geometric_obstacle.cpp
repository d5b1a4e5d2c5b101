// The geometric obstacle stage (include/maille/obstacle.hpp): one geometric fixed point and its
// contacts with the colliding points, far points culled by a bounding sphere.
#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <stdexcept>

#include "geometric_obstacle_view.hpp"
#include "maille/geometric_point.hpp"
#include "maille/mat3.hpp"
#include "maille/obstacle.hpp"
#include "maille/profile.hpp"
#include "maille/shared_laws.hpp"
#include "maille/state.hpp"
#include "obstacle_surface.hpp"
#include "point_contact_stage.hpp"

namespace maille {

namespace {

class GeometricObstacleStage final : public PointContactStage {
 public:
  GeometricObstacleStage(const Model& m, Obstacle o)
      : o_(std::move(o)),
        parameter_(shape_parameter(o_.shape, o_.shape_parameter)),
        set_(colliding_points(m, o_)),
        surface_(o_, o_.mesh ? o_.mesh : std::make_shared<const TriMesh>(obstacle_mesh(o_))) {
    if (o_.mesh)
      throw std::invalid_argument("obstacle '" + o_.name +
                                  "': a mesh has no canonical distance; use method \"facets\" "
                                  "or \"conditional\"");
    // The world bounding sphere: the canonical reach times the largest stretch of M_d. M_d =
    // R S has orthogonal columns, so its largest column is exactly its largest singular value.
    Real stretch = 0;
    for (const Vec3& e : {Vec3{1, 0, 0}, Vec3{0, 1, 0}, Vec3{0, 0, 1}})
      stretch = std::max(stretch, norm(o_.place.vector_to_world(e)));
    reach_ = shape_row(o_.shape).reach(parameter_) * stretch * Real(1 + 1e-9);
    member_.assign(m.points.size(), 0);
    for (const std::uint32_t p : set_) member_[p] = 1;
  }

  std::string name() const override { return obstacle_stage_name(o_); }
  GeometricObstacleView view() const { return {&o_, set_, reach_, thickness()}; }
  Phase phase() const override { return obstacle_phase(o_.method); }

  void scan(const State& s, const StageContext& ctx, Vec3* f) override {
    const Vec3* x = s.x().data();
    const Vec3* v = s.v().data();
    std::uint64_t contacts = 0;
    Real deepest = 0;
    const Real reach2 = reach_ * reach_;
    const shapes::Affine place = o_.motion.at(o_.place, ctx.t);
    const auto n = static_cast<std::int64_t>(set_.size());
    const int threads = std::max(1, ctx.threads);
    // Each particle's force is its own: threads share nothing but the two reductions.
#pragma omp parallel for schedule(static) num_threads(threads) if (threads > 1 && n > 4096) \
    reduction(+ : contacts) reduction(max : deepest)
    for (std::int64_t i = 0; i < n; ++i) {
      const std::uint32_t p = set_[i];
      const Vec3 rel = x[p] - place.translation;
      if (dot(rel, rel) > reach2) continue;  // far: one test
      const Contact c = contact(p, place, ctx.t, x[p], v[p], 0, false);
      if (c.depth <= 0 && !c.rubbing) continue;
      if (c.depth > 0) ++contacts;
      deepest = std::max(deepest, c.depth);
      if (f) f[p] += c.force;
    }
    count(ctx, o_.name, contacts, deepest);
  }

  // The penalty's energy, 1/2 k d^2 with d the world penetration: exact where the force is k d
  // along the world normal (world_normal, or a uniformly scaled shape), the energy of the world
  // depth otherwise.
  double energy(const Model&, const State& s) override {
    const Vec3* x = s.x().data();
    const shapes::Affine place = o_.motion.at(o_.place, s.time);
    double e = 0;
    for (const std::uint32_t p : set_) {
      const Vec3 rel = x[p] - place.translation;
      if (dot(rel, rel) > reach_ * reach_) continue;
      const Real d = contact(p, place, s.time, x[p], Vec3{}, 0, false).depth;
      if (d > 0) e += 0.5 * double(o_.stiffness) * double(d) * double(d);
    }
    return e;
  }

  // Implicit solvers (PointContacts): the same law at their iterate, with the stiffness
  // (k + z / h) n n^T along the world normal (exact for the world-normal variant and for uniform
  // scales; the force, which decides where the solve converges, is always the canonical one), and
  // friction's.
  // The shape's thinnest canonical extent (its row of the shape table: a torus's tube, a
  // cone's top, infinite for the plane) times the placement's smallest stretch, bounded below by
  // 1 / |M_i|_F (Frobenius >= largest singular value of the inverse): never more than the true
  // thickness.
  Real thickness() const override {
    const Real canonical = shape_row(o_.shape).thinnest(parameter_);
    Real f2 = 0;
    for (const auto& row : o_.place.inverse.m)
      for (const Real e : row) f2 += e * e;
    return canonical / std::sqrt(f2);
  }
  void set_time(double t) override {
    time_ = t;
    place_now_ = o_.motion.at(o_.place, t);
    lagged_ = false;
  }
  void lag(std::span<const std::uint32_t> points, const Vec3* x, const Vec3* v,
           double t_next) override {
    if (o_.friction > 0) {
      if (lag_normal_.size() != member_.size()) {
        lag_normal_.assign(member_.size(), Vec3{});
        lag_force_.assign(member_.size(), 0);
      }
      for (const std::uint32_t p : points) {
        if (!member_[p]) continue;
        const Contact c = contact(p, place_now_, time_, x[p], v[p], 0, false);
        lag_force_[p] = c.depth > 0 ? c.normal_force : 0;
        lag_normal_[p] = c.normal;
      }
    }
    set_time(t_next);
    lagged_ = o_.friction > 0;
  }
  void add_terms(std::span<const std::uint32_t> points, const Vec3* x, const Vec3* v, Real inv_h,
                 Vec3* f, Mat3* hessian, std::uint8_t* touching) const override {
    const Real reach2 = reach_ * reach_;
    for (const std::uint32_t p : points) {
      if (!member_[p]) continue;
      const Vec3 rel = x[p] - place_now_.translation;
      if (dot(rel, rel) > reach2 && !(lagged_ && lag_force_[p] > 0)) continue;
      const Contact c = contact(p, place_now_, time_, x[p], v[p], inv_h, lagged_);
      if (c.depth <= 0 && !c.rubbing) continue;
      f[p] += c.force;
      hessian[p] += c.stiffness;
      if (touching && c.depth > 0) touching[p] = 1;
    }
  }

  Vec3 push(std::uint32_t p, const Vec3& x) const override {
    if (!member_[p]) return {};
    const Vec3 at_rest = o_.motion.moves() ? o_.motion.velocity_at(x, time_) : Vec3{};
    const Contact c = contact(p, place_now_, time_, x, at_rest, 0, false);
    return c.depth > 0 ? c.force : Vec3{};
  }

  void surfaces(double t, std::vector<SurfaceInstance>& out) const override {
    surface_.add(o_, t, out);
  }

  // A particle touches one obstacle at a time. Through M_d the force is k times the world
  // penetration vector (M_d k M_i), so the world stiffness is k whatever the scale.
  void stability_terms(std::span<const Real>, std::span<Real> k_row,
                       std::span<Real> c_row) const override {
    for (std::uint32_t p : set_) {
      k_row[p] += o_.stiffness;
      c_row[p] += o_.damping;
    }
  }

 private:
  // Point p's contact at (x, v) with the obstacle placed at `place` (time t): the shared law
  // obstacle_contact_law (include/maille/detail/obstacle_laws.glsl, the GPU's too) at the
  // velocity relative to the surface: the penalty and its damper (the canonical law), then
  // friction mu F_n, viscous below kObstacleSlip; F_n and the normal are the contact's own, or
  // held from the step's start (`lagged`). `stiffness` is the block -df/dx - (1/h) df/dv for
  // implicit solvers: (k + z/h) n n^T, and for friction (mu F_n / max(|v_t|, slip)) / h
  // (I - n n^T), the friction's scale held (IPC's lagged form).
  struct Contact {
    Vec3 force, normal;
    Mat3 stiffness;
    Real depth = 0, normal_force = 0;
    bool rubbing = false;  // friction acts
  };
  Contact contact(std::uint32_t p, const shapes::Affine& place, double t, const Vec3& x,
                  const Vec3& v, Real inv_h, bool lagged) const {
    Contact c;
    const Vec3 vr = o_.motion.moves() ? v - o_.motion.velocity_at(x, t) : v;
    const Real held = lagged ? lag_force_[p] : 0;
    const Vec3 held_normal = lagged ? lag_normal_[p] : Vec3{};
    c.force = law::obstacle_contact_law(
        int(o_.shape), parameter_, place.direct, place.inverse, place.translation, x, vr,
        o_.stiffness, o_.damping, o_.world_normal, o_.friction, kObstacleSlip, inv_h, lagged, held,
        held_normal, c.depth, c.normal, c.normal_force, c.stiffness, c.rubbing);
    return c;
  }

  Obstacle o_;
  Real parameter_ = 0;  // the shape's parameter (shape_parameter: its default when unset)
  std::vector<std::uint32_t> set_;
  ObstacleSurface surface_;
  Real reach_ = 0;
  std::vector<std::uint8_t> member_;  // [points] 1 for the colliding points
  double time_ = 0;                   // of place_now_ (implicit solvers)
  shapes::Affine place_now_;
  bool lagged_ = false;           // friction's F_n and normal held from the step's start
  std::vector<Real> lag_force_;   // [points] held normal force, N (0: no contact at start)
  std::vector<Vec3> lag_normal_;  // [points] held unit normal
};

}  // namespace

GeometricObstacleView geometric_obstacle_view(const Stage& st) {
  const auto* g = dynamic_cast<const GeometricObstacleStage*>(&st);
  return g ? g->view() : GeometricObstacleView{};
}

std::unique_ptr<Stage> make_geometric_obstacle_stage(const Model& m, const Obstacle& o) {
  return std::make_unique<GeometricObstacleStage>(m, o);
}

}  // namespace maille
