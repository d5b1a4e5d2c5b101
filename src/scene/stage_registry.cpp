#include "maille/stage_registry.hpp"

#include <stdexcept>

#include "maille/limits.hpp"
#include "maille/obstacle.hpp"
#include "maille/self_collision.hpp"

namespace maille {

const StageRegistry::Entry* StageRegistry::find(std::string_view table) const {
  for (const auto& e : entries_)
    if (e.table == table) return &e;
  return nullptr;
}

namespace {

// The matrix rows hold, per colliding particle, every particle within R links: about
// (2 R + 1)^2 on grid cloth (4 bytes each). Refused before any allocation when that would not
// fit the memory budget (signatures keep rows for non-grid groups only, but a scene may be all
// ropes and lattices: the same bound is used).
void exclusion_fits(SceneTable& t, const Model& m, const SelfCollisionSettings& s) {
  if (s.exclusion == Exclusion::none || s.topological_radius == 0) return;
  std::uint64_t particles = 0;  // the free points of the colliding groups (every group: all)
  auto count = [&](std::uint32_t first, std::uint32_t n) {
    for (std::uint32_t p = first; p < first + n; ++p) particles += m.points.inv_mass[p] > 0;
  };
  if (s.groups.empty()) count(0, m.points.size());
  for (const auto& name : s.groups)
    if (const Group* g = m.group(name)) count(g->first, g->count);
  const double side = 2.0 * s.topological_radius + 1;
  const double bytes = double(particles) * side * side * 4;
  if (bytes > double(limits::memory_budget_bytes()))
    t.fail("topological_radius",
           "the exclusion rows would need about " + std::to_string(std::uint64_t(bytes)) +
               " bytes for " + std::to_string(particles) +
               " particles, above the memory budget: lower topological_radius");
}

// [self_collision]: docs/scene-format.md lists the keys.
StageSpec self_collision_table(SceneTable& t, const Model& m) {
  SelfCollisionSettings s;
  s.groups = t.texts("groups", {});
  for (const auto& g : s.groups)
    if (!m.group(g)) t.fail("groups", "no group named '" + g + "'");
  // The same bounds as every link's (limits.hpp): values beyond them overflow the arithmetic.
  s.radius = t.real("radius", 0, Bound::non_negative);
  t.check_range("radius", s.radius, 0, limits::max_coordinate, "m");
  s.stiffness = t.real("stiffness", s.stiffness, Bound::positive);
  t.check_range("stiffness", s.stiffness, 0, limits::max_stiffness, "N/m");
  s.damping = t.real("damping", s.damping, Bound::non_negative);
  t.check_range("damping", s.damping, 0, limits::max_stiffness, "N.s/m");
  s.friction = t.real("friction", s.friction, Bound::non_negative);
  t.check_range("friction", s.friction, 0, 1e3, "");
  const std::string bp =
      t.text("broad_phase", "uniform", {"brute", "uniform", "hashed", "hierarchical"});
  s.broad_phase = bp == "brute"     ? BroadPhase::brute
                  : bp == "hashed"  ? BroadPhase::hashed
                  : bp == "uniform" ? BroadPhase::uniform
                                    : BroadPhase::hierarchical;
  if (t.has_text("cell_size"))
    t.text("cell_size", "auto", {"auto"});
  else
    s.cell_size = t.real("cell_size", 0, Bound::positive);
  t.check_range("cell_size", s.cell_size, 0, limits::max_coordinate, "m");
  const std::string ex = t.text("exclusion", "signature", {"none", "matrix", "signature"});
  s.exclusion = ex == "none"     ? Exclusion::none
                : ex == "matrix" ? Exclusion::matrix
                                 : Exclusion::signature;
  s.topological_radius = static_cast<int>(t.integer("topological_radius", 2, 0, 16));
  exclusion_fits(t, m, s);
  if (t.text("primitive", "points", {"points", "triangles"}) == "triangles")
    s.primitive = Primitive::triangles;
  try {
    SelfCollisionSettings probe = s;  // checks groups, free points and the default radius
    probe.exclusion = Exclusion::none;
    const SelfCollisionEngine engine(m, probe);
    if (s.cell_size > 0 && s.cell_size < engine.settings().radius)
      t.fail("cell_size", "must be >= radius (" + std::to_string(engine.settings().radius) + " m)");
  } catch (const std::invalid_argument& e) {
    t.fail(s.groups.empty() ? "radius" : "groups", e.what());
  }
  return {"self_collision", Phase::forces,
          [s](const Model& model) { return make_self_collision_stage(model, s); }};
}

// [[obstacle]]: docs/scene-format.md. The geometric method is built; `facets` and `conditional`
// and mesh files are refused with a message until they are (issue: obstacles, Theme 2).
StageSpec obstacle_table(SceneTable& t, const Model& m) {
  GeometricObstacle o;
  o.name = t.text("name", "obstacle");
  const std::string method = t.text("method", "geometric", {"geometric", "facets", "conditional"});
  if (method != "geometric")
    t.fail("method",
           "method = \"" + method + "\" is not built yet in this version; use \"geometric\"");
  if (t.has("mesh")) t.fail("mesh", "mesh obstacles need method = \"facets\", not built yet");
  for (const char* other : {"threshold", "alpha", "beta", "motion"})
    if (t.has(other))
      t.fail(other,
             std::string("is not used by method = \"geometric\"") +
                 (std::string(other) == "motion" ? " (moving obstacles are not built yet)" : ""));
  const std::string shape = t.text(
      "shape", "sphere", {"sphere", "cube", "cylinder", "cone", "torus", "capsule", "plane"});
  o.shape = shape == "sphere"     ? ShapeKind::sphere
            : shape == "cube"     ? ShapeKind::cube
            : shape == "cylinder" ? ShapeKind::cylinder
            : shape == "cone"     ? ShapeKind::cone
            : shape == "torus"    ? ShapeKind::torus
            : shape == "capsule"  ? ShapeKind::capsule
                                  : ShapeKind::plane;
  if (o.shape != ShapeKind::torus && t.has("tube")) t.fail("tube", "only a torus has a tube");
  if (o.shape != ShapeKind::cone && t.has("top")) t.fail("top", "only a cone has a top radius");
  o.tube = t.real("tube", o.tube, Bound::positive);
  if (o.tube > 1) t.fail("tube", "must be in (0, 1] (tube radius / major radius)");
  o.top = t.real("top", o.top, Bound::non_negative);
  if (o.top > 1) t.fail("top", "must be in [0, 1] (top radius / bottom radius)");
  const Vec3 position = t.vec3("position", {0, 0, 0});
  const Vec3 rotation = t.vec3("rotation", {0, 0, 0});
  const Vec3 scale = t.vec3("scale", {1, 1, 1});
  if (!(scale.x > 1e-9 && scale.y > 1e-9 && scale.z > 1e-9))
    t.fail("scale", "every component must be > 1e-9 (M_i divides by it)");
  o.place = shapes::Affine::from(position, rotation, scale);
  o.stiffness = t.real("stiffness", o.stiffness, Bound::positive);
  t.check_range("stiffness", o.stiffness, 0, limits::max_stiffness, "N/m");
  o.damping = t.real("damping", o.damping, Bound::non_negative);
  t.check_range("damping", o.damping, 0, limits::max_stiffness, "N.s/m");
  o.world_normal = t.text("normal", "canonical", {"canonical", "world"}) == "world";
  o.collides_with = t.texts("collides_with", {});
  for (const auto& g : o.collides_with)
    if (!m.group(g)) t.fail("collides_with", "no group named '" + g + "'");
  try {
    make_geometric_obstacle_stage(m, o);  // checks that some free point collides
  } catch (const std::invalid_argument& e) {
    t.fail("collides_with", e.what());
  }
  return {"obstacle:" + o.name, Phase::forces,
          [o](const Model& model) { return make_geometric_obstacle_stage(model, o); }};
}

}  // namespace

// Built-in stage tables register here, one line each.
StageRegistry StageRegistry::with_builtins() {
  StageRegistry r;
  r.add({"self_collision", false,
         "self-collision of cloth and ropes: grids, topological exclusion, conditional response",
         self_collision_table});
  r.add({"obstacle", true, "fixed geometry: a canonical shape placed by an affine map",
         obstacle_table});
  return r;
}

}  // namespace maille
