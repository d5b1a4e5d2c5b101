#include "maille/stage_registry.hpp"

#include <stdexcept>
#include <vector>

#include "maille/fields.hpp"
#include "maille/group_contact.hpp"
#include "maille/integrator.hpp"
#include "maille/limits.hpp"
#include "maille/obstacle.hpp"
#include "maille/self_collision.hpp"
#include "maille/stage_keys.hpp"
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

// [self_collision]: the keys are declared in self_collision_keys() (docs/scene-format.md's
// table is checked against them). Validation runs without building the engine.
StageSpec self_collision_table(SceneTable& t, const Model& m) {
  SelfCollisionSettings s;
  s.groups = t.texts("groups", {});
  for (const auto& g : s.groups)
    if (!m.group(g)) t.fail("groups", "no group named '" + g + "'");
  if (t.has_text("cell_size"))
    t.text("cell_size", "auto", {"auto"});
  else
    s.cell_size = t.real("cell_size", 0, Bound::positive);
  t.check_range("cell_size", s.cell_size, 0, limits::max_coordinate, "m");
  read_keys(t, s, self_collision_keys());
  exclusion_fits(t, m, s);
  if (const StageProblem p = resolve_self_collision(m, s)) t.fail(p.key, p.message);
  StageSpec spec{std::string(kSelfCollisionStage), kSelfCollisionPhase,
                 [s](const Model& model) { return make_self_collision_stage(model, s); }};
  visit_keys(self_collision_keys(), s,
             [&](const StageKey<SelfCollisionSettings>& k, std::string v) {
               spec.parameters.emplace_back(std::string(k.key), std::move(v));
             });
  return spec;
}

}  // namespace

std::vector<DeclaredTable> declared_tables(const StageRegistry& stages) {
  std::vector<DeclaredTable> out;
  for (const auto& e : stages.entries())
    out.push_back({e.array ? "[[" + e.table + "]]" : "[" + e.table + "]", e.description, e.keys});
  out.push_back({"[fields.wind]", "wind on the surface's faces: mean velocity and gusts",
                 describe_keys(wind_keys(), WindField{})});
  out.push_back({"[simulation.implicit]",
                 "implicit Euler's solver and its iterations (methods: the solvers)",
                 describe_keys(implicit_keys(), ImplicitSettings{})});
  out.push_back({"[[contact]]",
                 "conditional spring-dampers between the points of two groups (CORDIS contacts)",
                 describe_keys(contact_keys(), GroupContactSpec{})});
  for (DeclaredTable& t : out)
    for (const auto& k : t.keys) t.methods = t.methods || k.methods != "all";
  return out;
}

std::vector<std::string> markdown_table(const DeclaredTable& t) {
  std::vector<std::string> lines{
      t.methods ? "| key | type | unit | default | range | methods | meaning |"
                : "| key | type | unit | default | range | meaning |",
      t.methods ? "|---|---|---|---|---|---|---|" : "|---|---|---|---|---|---|"};
  for (auto& row : markdown_rows(t.keys, t.methods)) lines.push_back(std::move(row));
  return lines;
}

// Built-in stage tables register here, one line each.
StageRegistry StageRegistry::with_builtins() {
  StageRegistry r;
  r.add({std::string(kSelfCollisionStage), false,
         "self-collision of cloth and ropes: grids, topological exclusion, conditional response",
         self_collision_table, describe_keys(self_collision_keys(), SelfCollisionSettings{})});
  r.add({"obstacle", true,
         "fixed or moving geometry (a canonical shape or a mesh file) by one of three methods: "
         "geometric, facets, conditional",
         obstacle_table, describe_keys(obstacle_keys(), Obstacle{})});
  return r;
}

}  // namespace maille
