#include "maille/stage_registry.hpp"

#include <stdexcept>
#include <vector>

#include "maille/limits.hpp"
#include "maille/self_collision.hpp"
#include "stage_tables.hpp"

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
  std::vector<std::uint8_t> in(m.points.size(), 0);  // the colliding groups (none named: all)
  auto mark = [&](std::uint32_t first, std::uint32_t n) {
    for (std::uint32_t p = first; p < first + n; ++p) in[p] = 1;
  };
  if (s.groups.empty()) mark(0, m.points.size());
  for (const auto& name : s.groups)
    if (const Group* g = m.group(name)) mark(g->first, g->count);
  std::vector<std::uint32_t> particles;  // their free points
  for (std::uint32_t p = 0; p < m.points.size(); ++p)
    if (in[p] && m.points.inv_mass[p] > 0) particles.push_back(p);
  // Measured by a bounded search from some particles (self_collision.hpp), not (2R + 1)^2:
  // bending links make rows longer (285 MB estimated, 1.28 GB used at R = 16 on 256^2).
  const std::uint64_t bytes = self_collision_exclusion_bytes(m, particles, s.topological_radius);
  if (bytes > limits::memory_budget_bytes())
    t.fail("topological_radius",
           "the exclusion rows would need about " + std::to_string(bytes) + " bytes for " +
               std::to_string(particles.size()) +
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

}  // namespace

// Built-in stage tables register here, one line each.
StageRegistry StageRegistry::with_builtins() {
  StageRegistry r;
  r.add({"self_collision", false,
         "self-collision of cloth and ropes: grids, topological exclusion, conditional response",
         self_collision_table});
  r.add({"obstacle", true,
         "fixed or moving geometry (a canonical shape or a mesh file) by one of three methods: "
         "geometric, facets, conditional",
         obstacle_table});
  return r;
}

}  // namespace maille
