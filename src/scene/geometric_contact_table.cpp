// [[link]] kind = "geometric_contact": a geometric point (a) and a free mass or a group (b, one
// contact per free point of it). Not a link brick: the tables of this kind are gathered by the
// stage registry (StageTableEntry::of_links) into the one stage that evaluates every geometric
// contact of the model (kGeometricContactStage).
#include <string>
#include <vector>

#include "maille/geometric_point.hpp"
#include "maille/stage_keys.hpp"
#include "point_ref.hpp"
#include "scene_keys.hpp"
#include "stage_tables.hpp"

namespace maille {

namespace {

// One table's contacts, appended to `out`.
void read_geometric_contact(SceneTable& t, const Model& m, std::vector<GeometricContact>& out) {
  GeometricContactTable table;  // geometric_contact_keys()
  read_key(t, table, geometric_contact_keys(), "a");
  const std::string& a = table.a;
  std::uint32_t g = 0;
  while (g < m.geometric_points.size() && m.geometric_points[g].name != a) ++g;
  if (g == m.geometric_points.size())
    t.fail("a", "no geometric point named '" + a +
                    "': a geometric contact links a [[geometric_point]] (a) to a free mass (b)");
  for (const char* key : {"stiffness", "damping", "normal"})
    read_key(t, table, geometric_contact_keys(), key);
  GeometricContact& c = table.contact;
  c.geometric = g;
  c.world_normal = table.normal == ContactNormal::world;
  const Group* group = t.has_text("b") ? m.group(t.text("b", "")) : nullptr;
  std::vector<std::uint32_t> points;
  if (group && group->count > 1) {
    for (std::uint32_t p = group->first; p < group->first + group->count; ++p)
      if (m.points.inv_mass[p] > 0) points.push_back(p);
    if (points.empty()) t.fail("b", "the group has no free point");
  } else {
    points.push_back(point_ref(t, "b", m));
    if (!(m.points.inv_mass[points[0]] > 0))
      t.fail("b", "must be a free mass: a geometric contact acts on a free mass only");
  }
  for (std::uint32_t p : points) {
    c.point = p;
    out.push_back(c);
  }
}

}  // namespace

std::optional<StageSpec> geometric_contact_links(std::span<SceneTable* const> tables, Model& m) {
  std::vector<GeometricContact> contacts;
  for (SceneTable* t : tables) read_geometric_contact(*t, m, contacts);
  return StageSpec{kGeometricContactStage, [contacts](const Model& model) {
                     return make_geometric_contact_stage(model, contacts);
                   }};
}

}  // namespace maille
