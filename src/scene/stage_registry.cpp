#include "maille/stage_registry.hpp"

#include <stdexcept>

#include "maille/self_collision.hpp"

namespace maille {

const StageRegistry::Entry* StageRegistry::find(std::string_view table) const {
  for (const auto& e : entries_)
    if (e.table == table) return &e;
  return nullptr;
}

namespace {

// [self_collision]: docs/scene-format.md lists the keys.
StageSpec self_collision_table(SceneTable& t, const Model& m) {
  SelfCollisionSettings s;
  s.groups = t.texts("groups", {});
  for (const auto& g : s.groups)
    if (!m.group(g)) t.fail("groups", "no group named '" + g + "'");
  s.radius = t.real("radius", 0, Bound::non_negative);
  s.stiffness = t.real("stiffness", s.stiffness, Bound::positive);
  s.damping = t.real("damping", s.damping, Bound::non_negative);
  s.friction = t.real("friction", s.friction, Bound::non_negative);
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
  const std::string ex = t.text("exclusion", "signature", {"none", "matrix", "signature"});
  s.exclusion = ex == "none"     ? Exclusion::none
                : ex == "matrix" ? Exclusion::matrix
                                 : Exclusion::signature;
  s.topological_radius = static_cast<int>(t.integer("topological_radius", 2, 0, 16));
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

}  // namespace

// Built-in stage tables register here, one line each.
StageRegistry StageRegistry::with_builtins() {
  StageRegistry r;
  r.add({"self_collision", false,
         "self-collision of cloth and ropes: grids, topological exclusion, conditional response",
         self_collision_table});
  return r;
}

}  // namespace maille
