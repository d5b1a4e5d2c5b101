#include "maille/stage_registry.hpp"

#include <algorithm>
#include <stdexcept>
#include <vector>

#include "audio_keys.hpp"
#include "builder_keys.hpp"
#include "maille/fields.hpp"
#include "maille/geometric_point.hpp"
#include "maille/group_contact.hpp"
#include "maille/integrator.hpp"
#include "maille/limits.hpp"
#include "maille/obstacle.hpp"
#include "maille/self_collision.hpp"
#include "maille/stage_keys.hpp"
#include "scene_keys.hpp"
#include "stage_tables.hpp"
#include "sweep_keys.hpp"

namespace maille {

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
  read_key(t, s, self_collision_keys(), "groups");
  for (const auto& g : s.groups)
    if (!m.group(g)) t.fail("groups", "no group named '" + g + "'");
  read_keys(t, s, self_collision_keys());
  exclusion_fits(t, m, s);
  if (const StageProblem p = resolve_self_collision(m, s)) t.fail(p.key, p.message);
  StageSpec spec{kSelfCollisionStage,
                 [s](const Model& model) { return make_self_collision_stage(model, s); }};
  visit_keys(self_collision_keys(), s,
             [&](const StageKey<SelfCollisionSettings>& k, std::string v) {
               spec.parameters.emplace_back(std::string(k.key), std::move(v));
             });
  return spec;
}

}  // namespace

namespace {

template <class S>
DeclaredTable declared(std::string table, std::string description,
                       std::span<const StageKey<S>> keys, const S& defaults = S{}) {
  return {std::move(table), std::move(description), describe_keys(keys, defaults)};
}

// A link kind's fields (link_kind.hpp: ParamField) as the docs show them, with the bound and
// the range the scene reader checks ([[link]]: limits::max_parameter).
std::vector<KeyInfo> describe_fields(const LinkKindRegistry::Entry& kind) {
  using key_detail::number_text;
  std::vector<KeyInfo> out;
  for (const ParamInfo& f : kind.fields) {
    KeyInfo i;
    i.key = f.name;
    i.type = "number";
    i.unit = unit_for_docs(f.unit);
    // Built by appending: GCC 12's -Wrestrict misreads "literal" + std::string at -O3.
    if (f.default_value)
      i.default_value = std::string("`").append(number_text(double(*f.default_value))).append("`");
    else if (f.default_is_distance)
      i.default_value = "the points' distance";
    else if (!f.default_from.empty())
      i.default_value = std::string("`").append(f.default_from).append("`");
    else
      i.default_value = "required";
    const std::string most = number_text(double(limits::max_parameter(f.unit)));
    i.range = f.bound == Bound::positive       ? std::string("(0, ")
              : f.bound == Bound::non_negative ? std::string("[0, ")
                                               : std::string("[-").append(most).append(", ");
    i.range.append(most).append("]");
    i.methods = "all";
    i.doc = f.doc;
    if (out.empty()) i.group = std::string("`").append(kind.keyword).append("`");
    out.push_back(std::move(i));
  }
  return out;
}

}  // namespace

std::vector<DeclaredTable> declared_tables(const StageRegistry& stages,
                                           const LinkKindRegistry& kinds) {
  std::vector<DeclaredTable> out;
  out.push_back(declared("[scene]", "the scene's name and description", scene_keys()));
  out.push_back(
      declared("[simulation]", "the time step, the scheme and the run", simulation_keys()));
  out.push_back(declared("[simulation.implicit]",
                         "implicit Euler's solver and its iterations (methods: the solvers)",
                         implicit_keys()));
  out.push_back(declared("[fields]", "forces on every free point", fields_keys()));
  out.push_back(declared("[fields.wind]", "wind on the surface's faces: mean velocity and gusts",
                         wind_keys()));
  out.push_back(
      declared("[[mass]]", "an explicit point: [[mass]] (free) or [[fixed]]", point_keys()));
  out.push_back(
      declared("drive", "a scripted path for fixed points (methods: the paths)", drive_keys()));
  out.push_back(declared("[[link]]", "one link between two points", link_keys()));
  {
    DeclaredTable fields{
        "[[link]] kinds", "each link kind's parameters (link_kind.hpp: fields)", {}};
    fields.group_column = "kind";
    for (const auto& kind : kinds.entries())
      for (auto& k : describe_fields(kind)) fields.keys.push_back(std::move(k));
    out.push_back(std::move(fields));
  }
  out.push_back(declared("[[listen]]", "one channel of the scene's sound", listen_keys()));
  out.push_back(declared("[audio]", "the sound's rate, format, gain and resampler", audio_keys()));
  out.push_back(declared("[[control]]", "a MIDI or OSC source mapped onto a scene key or a strike",
                         control_keys()));
  out.push_back(declared("[[control]] excite", "a control's strike or pluck", excite_keys()));
  for (const auto& e : stages.entries()) {
    std::string description = e.description;
    if (!e.stage.name.empty())  // the stage it makes (StageTableEntry::stage)
      description.append("; its stage: `")
          .append(e.stage.name)
          .append(e.array && e.stage.name.ends_with(':') ? "<name>" : "")
          .append("`, phase ")
          .append(to_string(e.stage.phase));
    const std::string table = e.of_links ? e.table
                              : e.array  ? "[[" + e.table + "]]"
                                         : "[" + e.table + "]";
    out.push_back({table, description, e.keys});
  }
  out.push_back(
      declared("[[obstacle]] motion", "an obstacle's motion (methods: the paths)", motion_keys()));
  out.push_back(
      declared("[[geometric_point]]", "a shape placed by an affine map", geometric_point_keys()));
  out.push_back(declared("[[flag]]", "cloth on a pole", flag_keys()));
  out.push_back(declared("[[rope]]", "rope or chain", rope_keys()));
  out.push_back(declared("[[net]]", "net of cords", net_keys()));
  out.push_back(declared("[[membrane]]", "drum skin with a closed boundary", membrane_keys()));
  out.push_back(declared("[[lattice]]", "soft 3-D block or ball", lattice_keys()));
  out.push_back(declared("[[floor]]", "ground of fixed points", floor_keys()));
  DeclaredTable sweep =
      declared("sweep file", "the keys of a sweep file (`maille sweep`)", sweep_keys(), Sweep{});
  sweep.page = "sweep.md";
  out.push_back(std::move(sweep));
  for (DeclaredTable& t : out)
    for (const auto& k : t.keys) t.methods = t.methods || k.methods != "all";
  return out;
}

std::vector<DeclaredTable> declared_tables(const StageRegistry& stages) {
  return declared_tables(stages, LinkKindRegistry::with_builtins());
}

std::vector<std::string> markdown_table(const DeclaredTable& t) {
  std::string header, rule;
  if (!t.group_column.empty())
    header.append("| ").append(t.group_column).append(" "), rule = "|---";
  header.append("| key | type | unit | default | range | ");
  rule.append("|---|---|---|---|---|");
  if (t.methods) header.append("methods | "), rule.append("---|");
  std::vector<std::string> lines{header.append("meaning |"), rule.append("---|")};
  const auto rows = markdown_rows(t.keys, t.methods);
  for (std::size_t i = 0; i < rows.size(); ++i) {
    std::string line;
    if (!t.group_column.empty())
      line.append("| ").append(t.keys[i].group).append(t.keys[i].group.empty() ? "" : " ");
    lines.push_back(line.append(rows[i]));
  }
  return lines;
}

std::string key_table_marker(const DeclaredTable& t) {
  return std::string("<!-- keys: ").append(t.table).append(" -->");
}

std::string with_declared_tables(std::string_view doc, std::span<const DeclaredTable> tables) {
  std::vector<std::string> lines;
  for (std::size_t at = 0; at <= doc.size();) {
    const std::size_t end = std::min(doc.find('\n', at), doc.size());
    lines.emplace_back(doc.substr(at, end - at));
    at = end + 1;
  }
  std::string out;
  for (std::size_t i = 0; i < lines.size(); ++i) {
    out += lines[i];
    if (i + 1 < lines.size()) out += '\n';
    const DeclaredTable* found = nullptr;
    for (const auto& t : tables)
      if (lines[i] == key_table_marker(t)) found = &t;
    if (!found) {
      if (lines[i].rfind("<!-- keys: ", 0) == 0)
        throw std::invalid_argument(
            std::string("'").append(lines[i]).append("' names no declared table"));
      continue;
    }
    for (const std::string& row : markdown_table(*found)) out.append(row).append("\n");
    while (i + 1 < lines.size() && lines[i + 1].rfind("|", 0) == 0) ++i;  // the old table
  }
  return out;
}

void register_stage_files(StageRegistry& r);  // generated: every file of src/stages/

// Built-in stage tables register here, one line each, then every file of src/stages/ (in the
// order of their names): the order in which a scene's tables are read, and so the order of its
// stages within a phase (the golden hashes').
StageRegistry StageRegistry::with_builtins() {
  StageRegistry r;
  // Gathered tables first, right after the [[link]] tables (the order is the golden hashes'):
  // the geometric contacts' stage, then [[contact]], whose links join the model's pools there.
  r.add({.table = "geometric_contact",
         .array = true,
         .description = "[[link]] kind = \"geometric_contact\": a geometric point (a) holding a "
                        "free mass or a group's free points (b) out of its shape",
         .keys = describe_keys(geometric_contact_keys(), GeometricContactTable{}),
         .gather = geometric_contact_links,
         .stage = kGeometricContactStage,
         .of_links = true});
  r.add({.table = "contact",
         .array = true,
         .description = "conditional spring-dampers between the points of two groups (CORDIS "
                        "contacts)",
         .keys = describe_keys(contact_keys(), GroupContactSpec{}),
         .gather = contact_tables,
         .stage = kGroupContactStage});
  r.add(
      {.table = std::string(kSelfCollisionStage.name),
       .description =
           "self-collision of cloth and ropes: grids, topological exclusion, conditional response",
       .parse = self_collision_table,
       .keys = describe_keys(self_collision_keys(), SelfCollisionSettings{}),
       .stage = kSelfCollisionStage});
  r.add({.table = "obstacle",
         .array = true,
         .description = "fixed or moving geometry (a canonical shape or a mesh file) by one of "
                        "three methods: geometric, facets, conditional",
         .parse = obstacle_table,
         .keys = describe_keys(obstacle_keys(), Obstacle{}),
         .stage = {kObstacleStagePrefix, obstacle_phase(Obstacle{}.method)}});
  register_stage_files(r);
  return r;
}

}  // namespace maille
