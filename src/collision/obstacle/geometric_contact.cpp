// Geometric contacts (include/maille/geometric_point.hpp): the law, and the stage of the bricks.
#include <algorithm>
#include <array>
#include <stdexcept>

#include "maille/geometric_point.hpp"
#include "maille/model.hpp"
#include "maille/profile.hpp"
#include "maille/state.hpp"

namespace maille {

Vec3 geometric_contact_force(const GeometricPoint& g, const shapes::Affine& place, const Vec3& x,
                             const Vec3& v, Real stiffness, Real damping, bool world_normal,
                             Real& depth, Vec3* normal) {
  depth = 0;
  const Vec3 c = place.to_canonical(x);  // (A) into the canonical frame through M_i
  const shapes::Distance d = shapes::canonical(g.shape, c, g.top, g.tube);  // (B)
  if (!d.inside()) return {};
  const Vec3 pen_c = d.penetration();  // (C) the canonical penetration vector
  if (normal) {
    const Vec3 n = place.normal_to_world(d.normal);
    *normal = n * (Real(1) / (norm(n) + Real(1e-300)));
  }
  if (!world_normal) {
    // The brief's mapping: the spring-damper on the canonical penetration, back through M_d.
    const Vec3 vc = place.vector_to_canonical(v);
    depth = norm(place.vector_to_world(pen_c));
    return place.vector_to_world(pen_c * stiffness - d.normal * (damping * dot(vc, d.normal)));
  }
  // Along the world normal, with the world depth of the canonical penetration along it.
  const Vec3 n = place.normal_to_world(d.normal);
  depth = std::max<Real>(dot(place.vector_to_world(pen_c), n), 0);
  return n * (stiffness * depth - damping * dot(v, n));
}

namespace {

class GeometricContactStage final : public Stage {
 public:
  GeometricContactStage(const Model& m, std::vector<GeometricContact> contacts)
      : contacts_(std::move(contacts)) {
    for (const GeometricContact& c : contacts_) {
      if (c.geometric >= m.geometric_points.size())
        throw std::invalid_argument("geometric contact to a geometric point that does not exist");
      if (c.point >= m.points.size() || !(m.points.inv_mass[c.point] > 0))
        throw std::invalid_argument("a geometric contact links a geometric point to a free mass");
    }
  }

  std::string name() const override { return std::string(kGeometricContactStage); }
  Phase phase() const override { return kGeometricContactPhase; }

  void apply(const Model& m, State& s, const StageContext& ctx) override {
    const Vec3* x = s.x().data();
    const Vec3* v = s.v().data();
    Vec3* f = s.f().data();
    std::uint64_t active = 0;
    Real deepest = 0;
    for (const GeometricContact& c : contacts_) {
      const GeometricPoint& g = m.geometric_points[c.geometric];
      Real depth = 0;
      f[c.point] += geometric_contact_force(g, g.place, x[c.point], v[c.point], c.stiffness,
                                            c.damping, c.world_normal, depth);
      active += depth > 0;
      deepest = std::max(deepest, depth);
    }
    if (!ctx.profile) return;
    if (ids_[0] < 0)
      ids_ = {ctx.profile->counter("geometric_contacts_active"),
              ctx.profile->gauge("geometric_contacts_depth")};
    ctx.profile->set_count(ids_[0], active);
    ctx.profile->set_gauge(ids_[1], deepest);
  }

  // Through M_d the force is k times the world penetration, so each contact is a stiffness k.
  void stability_terms(std::span<const Real>, std::span<Real> k_row,
                       std::span<Real> c_row) const override {
    for (const GeometricContact& c : contacts_) {
      k_row[c.point] += c.stiffness;
      c_row[c.point] += c.damping;
    }
  }

 private:
  std::vector<GeometricContact> contacts_;
  std::array<int, 2> ids_{-1, -1};
};

}  // namespace

std::unique_ptr<Stage> make_geometric_contact_stage(const Model& m,
                                                    std::vector<GeometricContact> contacts) {
  return std::make_unique<GeometricContactStage>(m, std::move(contacts));
}

}  // namespace maille
