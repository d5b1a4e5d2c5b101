// [[contact]]: conditional spring-dampers between the points of two groups (CORDIS contacts).
// A table by links (`method = "links"`) adds one conditional link per pair of points to the
// model; the broad-phase tables make one stage together (kGroupContactStage), which finds the
// close pairs at every step. Registered in stage_registry.cpp as a gathered table: the scene
// reader hands it every [[contact]] at once, right after the [[link]] tables (the links keep
// their place in the model's pools), before the other stage tables. The keys are declared in
// contact_keys() (group_contact_keys.cpp); `between` is read here, since it names groups of
// the model.
#include <cstdint>
#include <string>
#include <vector>

#include "maille/builders.hpp"
#include "maille/group_contact.hpp"
#include "maille/limits.hpp"
#include "maille/stage_keys.hpp"
#include "stage_tables.hpp"

namespace maille {

namespace {

constexpr std::size_t kMaxContactLinks = 20'000'000;

// The two groups of `between`, checked: named, existing and different.
std::array<const Group*, 2> between(SceneTable& t, const Model& m) {
  const std::vector<std::string> names =
      t.has("between") ? t.texts("between", {}) : std::vector<std::string>{};
  if (names.size() != 2) t.fail("between", "must name two groups: between = [\"a\", \"b\"]");
  std::array<const Group*, 2> g{};
  for (std::size_t i = 0; i < 2; ++i) {
    g[i] = m.group(names[i]);
    if (!g[i]) t.fail_item("between", i, "no group named '" + names[i] + "'");
  }
  if (g[0] == g[1]) t.fail("between", "the two groups must differ (self-collision is a stage)");
  return g;
}

// A broad-phase table's groups: some free point, no point shared.
void check_broad_phase(SceneTable& t, const Model& m, const std::array<const Group*, 2>& g) {
  bool any_free = false;
  for (const Group* gr : g)
    for (std::uint32_t i = gr->first; i < gr->first + gr->count && !any_free; ++i)
      any_free = m.points.inv_mass[i] > 0;
  if (!any_free) t.fail("between", "the two groups hold no free point: nothing can collide");
  if (g[0]->first < g[1]->first + g[1]->count && g[1]->first < g[0]->first + g[0]->count)
    t.fail("between", "the two groups share points");
}

// A table by links: every pair of the two groups, within the size budget.
void add_contact_links(SceneTable& t, Model& m, const std::array<const Group*, 2>& g,
                       const GroupContactSpec& c) {
  const std::uint64_t pairs = std::uint64_t(g[0]->count) * g[1]->count;
  const limits::SizeEstimate total{m.points.size(), m.links.total() + pairs,
                                   m.surface.triangles.size()};
  const std::string too_big = limits::check_size(total);
  if (pairs > kMaxContactLinks || !too_big.empty())
    t.fail("between", "too many pairs: " + std::to_string(g[0]->count) + " x " +
                          std::to_string(g[1]->count) + " = " + std::to_string(pairs) +
                          " conditional links (limit " + std::to_string(kMaxContactLinks) + ")" +
                          (too_big.empty() ? "" : "; " + too_big));
  build_contacts(m, *g[0], *g[1], {c.stiffness, c.damping, c.threshold, c.rest_length});
}

// One stage for every broad-phase table; its parameters are each table's declared keys
// ("contact[0].stiffness", ...), which `maille info` shows and checkpoints' fingerprints hash.
StageSpec group_contacts_stage(const std::vector<GroupContactSpec>& specs) {
  StageSpec spec{kGroupContactStage,
                 [specs](const Model& model) { return make_group_contact_stage(model, specs); }};
  for (std::size_t i = 0; i < specs.size(); ++i)
    visit_keys(contact_keys(), specs[i], [&](const StageKey<GroupContactSpec>& k, std::string v) {
      spec.parameters.emplace_back("contact[" + std::to_string(i) + "]." + std::string(k.key),
                                   std::move(v));
    });
  return spec;
}

}  // namespace

std::optional<StageSpec> contact_tables(std::span<SceneTable* const> tables, Model& m) {
  std::vector<GroupContactSpec> broad_phase;
  for (SceneTable* t : tables) {
    const std::array<const Group*, 2> g = between(*t, m);
    GroupContactSpec c{g[0]->name, g[1]->name};
    read_keys(*t, c, contact_keys());
    if (c.method == ContactMethod::broad_phase) {
      check_broad_phase(*t, m, g);
      broad_phase.push_back(std::move(c));
    } else {
      add_contact_links(*t, m, g, c);
    }
    t->finish();  // each table's unknown keys before the next table's errors, as read
  }
  if (broad_phase.empty()) return std::nullopt;
  return group_contacts_stage(broad_phase);
}

}  // namespace maille
