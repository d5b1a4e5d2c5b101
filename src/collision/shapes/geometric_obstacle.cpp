// The geometric obstacle stage (include/maille/obstacle.hpp).
#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "maille/obstacle.hpp"
#include "maille/profile.hpp"
#include "maille/state.hpp"

namespace maille {

namespace {

// Radius of a canonical sphere about the origin holding the shape (infinite for the plane).
Real canonical_reach(const GeometricObstacle& o) {
  switch (o.shape) {
    case ShapeKind::sphere:
      return 1;
    case ShapeKind::cube:
      return std::sqrt(Real(3));
    case ShapeKind::cylinder:
    case ShapeKind::cone:
      return std::sqrt(Real(2));
    case ShapeKind::torus:
      return 1 + o.tube;
    case ShapeKind::capsule:
      return 2;
    case ShapeKind::plane:
      return std::numeric_limits<Real>::infinity();
  }
  return std::numeric_limits<Real>::infinity();
}

class GeometricObstacleStage final : public Stage {
 public:
  GeometricObstacleStage(const Model& m, GeometricObstacle o) : o_(std::move(o)) {
    std::vector<std::uint8_t> in(m.points.size(), o_.collides_with.empty() ? 1 : 0);
    for (const auto& name : o_.collides_with) {
      const Group* g = m.group(name);
      if (!g)
        throw std::invalid_argument("obstacle '" + o_.name + "': no group named '" + name + "'");
      std::fill(in.begin() + g->first, in.begin() + g->first + g->count, 1);
    }
    for (std::uint32_t p = 0; p < m.points.size(); ++p)
      if (in[p] && m.points.inv_mass[p] > 0) set_.push_back(p);
    if (set_.empty())
      throw std::invalid_argument("obstacle '" + o_.name + "': no free point collides with it");
    // The world bounding sphere: the canonical reach times the largest stretch of M_d.
    Real stretch = 0;
    for (const Vec3& e : {Vec3{1, 0, 0}, Vec3{0, 1, 0}, Vec3{0, 0, 1}})
      stretch = std::max(stretch, norm(o_.place.vector_to_world(e)));
    reach_ = canonical_reach(o_) * stretch * std::sqrt(Real(3));
  }

  std::string name() const override { return "obstacle:" + o_.name; }
  Phase phase() const override { return Phase::forces; }

  void apply(const Model&, State& s, const StageContext& ctx) override {
    const Vec3* x = s.x().data();
    const Vec3* v = s.v().data();
    Vec3* f = s.f().data();
    std::uint64_t contacts = 0;
    Real deepest = 0;
    const Real reach2 = reach_ * reach_;
    for (std::uint32_t p : set_) {
      const Vec3 rel = x[p] - o_.place.translation;
      if (dot(rel, rel) > reach2) continue;  // far: one test
      const Vec3 c = o_.place.to_canonical(x[p]);
      const shapes::Distance d = shapes::canonical(o_.shape, c, o_.top, o_.tube);
      if (!d.inside()) continue;
      ++contacts;
      const Vec3 pen_c = d.penetration();
      Vec3 force;
      if (!o_.world_normal) {
        // The brief's mapping: a spring-damper on the canonical penetration, back through M_d.
        const Vec3 vc = o_.place.vector_to_canonical(v[p]);
        force = o_.place.vector_to_world(pen_c * o_.stiffness -
                                         d.normal * (o_.damping * dot(vc, d.normal)));
        deepest = std::max(deepest, norm(o_.place.vector_to_world(pen_c)));
      } else {
        // Along the world normal, with the world depth of the canonical penetration along it.
        const Vec3 n = o_.place.normal_to_world(d.normal);
        const Real depth = std::max<Real>(dot(o_.place.vector_to_world(pen_c), n), 0);
        force = n * (o_.stiffness * depth - o_.damping * dot(v[p], n));
        deepest = std::max(deepest, depth);
      }
      f[p] += force;
    }
    if (!ctx.profile) return;
    if (ids_[0] < 0)
      ids_ = {ctx.profile->counter("obstacle_" + o_.name + "_contacts"),
              ctx.profile->gauge("obstacle_" + o_.name + "_depth")};
    ctx.profile->set_count(ids_[0], contacts);
    ctx.profile->set_gauge(ids_[1], deepest);
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
  GeometricObstacle o_;
  std::vector<std::uint32_t> set_;
  Real reach_ = 0;
  std::array<int, 2> ids_{-1, -1};
};

}  // namespace

std::unique_ptr<Stage> make_geometric_obstacle_stage(const Model& m, const GeometricObstacle& o) {
  return std::make_unique<GeometricObstacleStage>(m, o);
}

}  // namespace maille
