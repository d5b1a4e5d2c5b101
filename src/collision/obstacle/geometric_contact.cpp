// Geometric contacts (include/maille/geometric_point.hpp): the law, and the stage of the bricks.
#include <algorithm>
#include <array>
#include <stdexcept>

#include "maille/geometric_point.hpp"
#include "maille/model.hpp"
#include "maille/profile.hpp"
#include "maille/shared_laws.hpp"
#include "maille/state.hpp"

namespace maille {

// The shared law (include/maille/detail/obstacle_laws.glsl), which the GPU's kernels paste.
Vec3 geometric_contact_force(const GeometricPoint& g, const shapes::Affine& place, const Vec3& x,
                             const Vec3& v, Real stiffness, Real damping, bool world_normal,
                             Real& depth, Vec3* normal) {
  Vec3 n;
  const Vec3 f = law::geometric_contact_law(
      int(g.shape), shape_parameter(g.shape, g.shape_parameter), place.direct, place.inverse,
      place.translation, x, v, stiffness, damping, world_normal, depth, n);
  if (normal && !(n == Vec3{})) *normal = n;  // inside (the law's normal is zero outside)
  return f;
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

  std::string name() const override { return std::string(kGeometricContactStage.name); }
  Phase phase() const override { return kGeometricContactStage.phase; }

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
    if (ctx.profile) columns_.set(*ctx.profile, {active, deepest});
  }

  // 1/2 k d^2 per contact, d the world penetration (geometric_obstacle.cpp says when exact).
  double energy(const Model& m, const State& s) override {
    double e = 0;
    for (const GeometricContact& c : contacts_) {
      const GeometricPoint& g = m.geometric_points[c.geometric];
      Real depth = 0;
      geometric_contact_force(g, g.place, s.x()[c.point], Vec3{}, c.stiffness, c.damping,
                              c.world_normal, depth);
      if (depth > 0) e += 0.5 * double(c.stiffness) * double(depth) * double(depth);
    }
    return e;
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
  ProfileColumns columns_{{"geometric_contacts_active"}, {"geometric_contacts_depth", true}};
};

}  // namespace

std::unique_ptr<Stage> make_geometric_contact_stage(const Model& m,
                                                    std::vector<GeometricContact> contacts) {
  return std::make_unique<GeometricContactStage>(m, std::move(contacts));
}

}  // namespace maille
