// Names and keys declared once (names.hpp, stage_keys.hpp): every name table round-trips and
// covers its enum, the documentation lists exactly the declared names and keys, and the scene
// reader's parsing, range errors, method gate and resolved values all come from the
// declarations.
#include <gtest/gtest.h>

#include <algorithm>
#include <fstream>
#include <set>
#include <sstream>

#include "maille/audio.hpp"
#include "maille/backend.hpp"
#include "maille/builders.hpp"
#include "maille/geometric_point.hpp"
#include "maille/group_contact.hpp"
#include "maille/integrator.hpp"
#include "maille/io.hpp"
#include "maille/link_registry.hpp"
#include "maille/obstacle.hpp"
#include "maille/scene.hpp"
#include "maille/self_collision.hpp"
#include "maille/stage_keys.hpp"
#include "maille/stage_registry.hpp"

namespace {

using namespace maille;

Result<Scene> parse(const std::string& text) {
  static const LinkKindRegistry kinds = LinkKindRegistry::with_builtins();
  return parse_scene(text, "t.toml", kinds);
}

std::vector<std::string> doc_lines(const char* file) {
  std::ifstream in(std::string(MAILLE_SOURCE_DIR) + "/" + file);
  std::vector<std::string> lines;
  for (std::string l; std::getline(in, l);) lines.push_back(l);
  return lines;
}

// The docs' row of `key` in the section whose heading starts with `heading` ("" when absent).
std::string doc_row(const std::vector<std::string>& doc, std::string_view heading,
                    std::string_view key) {
  std::size_t i = 0;
  while (i < doc.size() && doc[i].rfind(heading, 0) != 0) ++i;
  const std::string start = "| `" + std::string(key) + "` |";
  for (++i; i < doc.size() && doc[i].rfind("## ", 0) != 0 && doc[i].rfind("### ", 0) != 0; ++i)
    if (doc[i].rfind(start, 0) == 0) return doc[i];
  return {};
}

template <Named E>
void expect_round_trip() {
  const auto& names = NameTable<E>::names;
  std::set<std::string_view> seen;
  for (std::size_t i = 0; i < names.size(); ++i) {
    // Enums are 0, 1, 2...: the table lists every value, in any order, once.
    const E value = static_cast<E>(i);
    EXPECT_NE(to_string(value), "?") << NameTable<E>::what << " value " << i << " has no name";
    EXPECT_EQ(parse_name<E>(to_string(value)), value) << NameTable<E>::what;
    EXPECT_TRUE(seen.insert(names[i].name).second) << "duplicate name " << names[i].name;
    EXPECT_FALSE(names[i].doc.empty()) << names[i].name;
  }
  EXPECT_FALSE(parse_name<E>("no_such_name"));
}

// The docs' row lists exactly the table's names, in the table's order.
template <Named E>
void expect_documented(std::string_view heading, std::string_view key) {
  static const auto doc = doc_lines("docs/scene-format.md");
  const std::string row = doc_row(doc, heading, key);
  ASSERT_FALSE(row.empty()) << heading << " " << key << ": no row in docs/scene-format.md";
  std::string listed;
  for (const auto& n : NameTable<E>::names)
    listed += (listed.empty() ? "`" : ", `") + std::string(n.name) + "`";
  EXPECT_NE(row.find("| " + listed + " |"), std::string::npos)
      << heading << " " << key << ": the docs should list " << listed << "\n  row: " << row;
}

TEST(Names, EveryTableRoundTripsAndCoversItsEnum) {
  expect_round_trip<BroadPhase>();
  expect_round_trip<Phase>();
  expect_round_trip<PointKind>();
  expect_round_trip<Exclusion>();
  expect_round_trip<Primitive>();
  expect_round_trip<ObstacleMethod>();
  // The shapes are a table of their own (shapes.hpp): each row's value is its index.
  {
    std::set<std::string_view> seen;
    for (std::size_t i = 0; i < shape_table().size(); ++i) {
      const ShapeKind shape = static_cast<ShapeKind>(i);
      EXPECT_EQ(parse_shape(to_string(shape)), shape);
      EXPECT_TRUE(seen.insert(to_string(shape)).second) << "duplicate name " << to_string(shape);
      EXPECT_FALSE(shape_row(shape).doc.empty()) << to_string(shape);
    }
    EXPECT_FALSE(parse_shape("no_such_name"));
    EXPECT_THROW(shape_kind("no_such_name"), std::invalid_argument);
  }
  expect_round_trip<FlagFixed>();
  expect_round_trip<RopeFixed>();
  expect_round_trip<NetFixed>();
  expect_round_trip<LatticeFixed>();
  expect_round_trip<LatticeShape>();
  expect_round_trip<BackendKind>();
  expect_round_trip<ImplicitSolver>();
  expect_round_trip<FrameFormat>();
  expect_round_trip<audio::Quantity>();
  expect_round_trip<audio::SampleFormat>();
  expect_round_trip<audio::Resampler>();
  expect_round_trip<DrivePath::Kind>();
  expect_round_trip<ContactNormal>();
  expect_round_trip<ContactMethod>();
  // Motion paths: every value but `none` (not a name a scene may give).
  for (const auto& n : NameTable<ObstacleMotion::Kind>::names) {
    EXPECT_NE(n.value, ObstacleMotion::Kind::none);
    EXPECT_EQ(parse_name<ObstacleMotion::Kind>(n.name), n.value);
  }
  EXPECT_EQ(NameTable<ObstacleMotion::Kind>::names.size(), 3u);
}

TEST(Names, TheDocsListEveryTablesNames) {
  expect_documented<BroadPhase>("## Self-collision", "broad_phase");
  expect_documented<Exclusion>("## Self-collision", "exclusion");
  expect_documented<Primitive>("## Self-collision", "primitive");
  expect_documented<IntersectionCheck>("## Self-collision", "check");
  expect_documented<ObstacleMethod>("## Obstacles", "method");
  {  // the shape table's names, in its order
    static const auto doc = doc_lines("docs/scene-format.md");
    std::string listed;
    for (const std::string_view name : shape_names())
      listed += (listed.empty() ? "`" : ", `") + std::string(name) + "`";
    EXPECT_NE(doc_row(doc, "## Obstacles", "shape").find("| " + listed + " |"), std::string::npos)
        << listed;
  }
  expect_documented<ContactNormal>("## Obstacles", "normal");
  expect_documented<ContactMethod>("## Contacts", "method");
  expect_documented<FlagFixed>("### `[[flag]]`", "fixed");
  expect_documented<RopeFixed>("### `[[rope]]`", "fixed");
  expect_documented<NetFixed>("### `[[net]]`", "fixed");
  expect_documented<LatticeFixed>("### `[[lattice]]`", "fixed");
  expect_documented<LatticeShape>("### `[[lattice]]`", "shape");
  expect_documented<BackendKind>("## `[simulation]`", "backend");
  expect_documented<ImplicitSolver>("### `[simulation.implicit]`", "solver");
  expect_documented<audio::Quantity>("## Sound", "quantity");
  expect_documented<audio::SampleFormat>("## Sound", "format");
  expect_documented<audio::Resampler>("## Sound", "resampler");
  expect_documented<DrivePath::Kind>("### `drive`", "path");
  expect_documented<ObstacleMotion::Kind>("`motion` (inline", "path");
  // The integrators are a registry: the docs list its names, in its order.
  {
    static const auto doc = doc_lines("docs/scene-format.md");
    std::string listed;
    for (const auto& e : IntegratorRegistry::builtin().entries())
      listed += (listed.empty() ? "`" : ", `") + e.name + "`";
    EXPECT_NE(doc_row(doc, "## `[simulation]`", "integrator").find("| " + listed + " |"),
              std::string::npos)
        << listed;
  }
  // The frame formats are command-line choices: README's synopsis lists them.
  bool listed = false;
  for (const auto& line : doc_lines("README.md"))
    listed = listed || line.find("--format " + name_list<FrameFormat>("|")) != std::string::npos;
  EXPECT_TRUE(listed) << "README.md should show --format " << name_list<FrameFormat>("|");
}

TEST(Names, AChoiceOffTheTableIsRefusedWithTheTablesList) {
  const auto r = parse("[[rope]]\nfixed = \"middle\"\n");
  ASSERT_FALSE(r);
  EXPECT_EQ(r.error().message, "must be one of " + name_list<RopeFixed>() + " (got 'middle')");
}

// docs/scene-format.md's key tables are the declarations, row for row, for every table a scene
// may hold: each stands after its `<!-- keys: TABLE -->` line, and the file equals itself with
// every such table regenerated (`maille info --keys --update-docs docs/scene-format.md`).
TEST(StageKeys, TheDocsTablesAreTheDeclarations) {
  const auto doc = doc_lines("docs/scene-format.md");
  std::string text;
  for (const auto& line : doc) text += line + "\n";
  const auto tables = declared_tables(StageRegistry::with_builtins());
  ASSERT_GE(tables.size(), 20u);
  std::set<std::string> names;
  for (const DeclaredTable& t : tables) {
    EXPECT_TRUE(names.insert(t.table).second) << t.table << " is declared twice";
    if (t.page != "scene-format.md") continue;  // the sweep file's (sweep.md), below
    std::size_t i = 0;
    while (i < doc.size() && doc[i] != key_table_marker(t)) ++i;
    ASSERT_LT(i, doc.size()) << "docs/scene-format.md has no " << key_table_marker(t);
    const std::vector<std::string> want = markdown_table(t);
    for (std::size_t k = 0; k < want.size(); ++k)
      EXPECT_EQ(i + 1 + k < doc.size() ? doc[i + 1 + k] : "", want[k]) << t.table << " row " << k;
    EXPECT_TRUE(i + 1 + want.size() >= doc.size() || doc[i + 1 + want.size()].rfind("|", 0) != 0)
        << t.table << ": the docs have more rows than declared keys";
  }
  EXPECT_EQ(with_declared_tables(text, tables), text);
  // No key table is written by hand: every one follows a marker.
  for (std::size_t i = 0; i < doc.size(); ++i) {
    if (doc[i].rfind("| key |", 0) == 0 || doc[i].rfind("| kind | key |", 0) == 0) {
      EXPECT_TRUE(i > 0 && doc[i - 1].rfind("<!-- keys: ", 0) == 0)
          << "line " << i + 1 << ": a key table without its <!-- keys: TABLE --> line";
    }
  }
  EXPECT_THROW(with_declared_tables("<!-- keys: [nothing] -->\n", tables), std::invalid_argument);
}

// The other pages with key tables hold them the same way: docs/sound.md ([[listen]], [audio],
// [[control]] and its excite table) and docs/sweep.md (the sweep file, whose declared page it
// is): each after its marker, equal to the declaration, none written by hand.
TEST(StageKeys, TheOtherPagesTablesAreTheDeclarations) {
  const auto tables = declared_tables(StageRegistry::with_builtins());
  for (const std::string page : {"sound.md", "sweep.md"}) {
    const auto doc = doc_lines(("docs/" + page).c_str());
    std::string text;
    for (const auto& line : doc) text += line + "\n";
    EXPECT_EQ(with_declared_tables(text, tables), text)
        << "run: maille info --keys --update-docs docs/" << page;
    std::size_t markers = 0;
    for (std::size_t i = 0; i < doc.size(); ++i) {
      markers += doc[i].rfind("<!-- keys: ", 0) == 0;
      if (doc[i].rfind("| key |", 0) == 0) {
        EXPECT_TRUE(i > 0 && doc[i - 1].rfind("<!-- keys: ", 0) == 0)
            << "docs/" << page << " line " << i + 1 << ": a key table without its marker";
      }
    }
    EXPECT_GE(markers, 1u) << page;
    for (const DeclaredTable& t : tables) {
      if (t.page != page) continue;
      EXPECT_NE(std::find(doc.begin(), doc.end(), key_table_marker(t)), doc.end())
          << "docs/" << page << " has no " << key_table_marker(t);
    }
  }
}

// The scene's own tables and the builders read through their declarations: a default taken
// from another key, a bound, a range and a check, with the messages the getters always gave.
TEST(StageKeys, SceneAndBuilderKeysComeFromTheirDeclarations) {
  auto error = [](const std::string& table) {
    const auto r = parse(table);
    return r ? std::string("no error") : r.error().key + " | " + r.error().message;
  };
  EXPECT_EQ(error("[simulation]\nstep = 0\n[[mass]]\nposition = [0, 0, 0]\n"),
            "simulation.step | must be > 0 (got 0)");
  EXPECT_EQ(error("[simulation]\nintegrator = \"euler\"\n"),
            "simulation.integrator | unknown integrator 'euler' (known: " +
                IntegratorRegistry::builtin().names() + ")");
  EXPECT_EQ(error("[[mass]]\nmass = 1\n"), "mass[0].position | is required but missing");
  EXPECT_EQ(error("[[rope]]\npretension = 1\n"), "rope[0].pretension | must be < 1");
  EXPECT_EQ(error("[[flag]]\nstiffness = 2e12\n"),
            "flag[0].stiffness | must be in [0, 1e+12] N/m (got 2e+12)");
  EXPECT_EQ(error("[[fixed]]\nposition = [0, 0, 0]\nvelocity = [1, 0, 0]\n")
                .rfind("fixed[0].velocity | unknown key", 0),
            0u);
  auto r = parse("[[flag]]\nstiffness = 400\nresolution = [4, 3]\n");
  ASSERT_TRUE(r) << r.error().to_string();
  FlagParams want;
  want.material.stiffness = 400;
  want.shear_stiffness = 200;   // stiffness / 2
  want.bending_stiffness = 40;  // stiffness / 10
  want.nx = 4;
  want.ny = 3;
  Model m;
  build_flag(m, want, "flag0");
  EXPECT_EQ(r->model.points.size(), m.points.size());
  EXPECT_EQ(r->model.links.total(), m.links.total());
}

const char* kCloth = R"(
[[flag]]
name = "cloth"
resolution = [6, 4]
)";

TEST(StageKeys, EveryDeclaredKeyIsReadAndVisited) {
  const std::string text = std::string(kCloth) + R"(
[self_collision]
radius = 0.05
stiffness = 750
damping = 0.25
friction = 0.5
broad_phase = "hashed"
cell_size = 0.08
exclusion = "matrix"
topological_radius = 3
primitive = "triangles"
check = "every_step"
groups = ["cloth"]
)";
  auto r = parse(text);
  ASSERT_TRUE(r) << r.error().to_string();
  ASSERT_EQ(r->model.stages.size(), 1u);
  const auto& p = r->model.stages[0].parameters;
  ASSERT_EQ(p.size(), self_collision_keys().size());  // every key visited, in order
  const std::vector<std::pair<std::string, std::string>> want{
      {"groups", "cloth"},        {"radius", "0.05"},      {"stiffness", "750"},
      {"damping", "0.25"},        {"friction", "0.5"},     {"broad_phase", "hashed"},
      {"cell_size", "0.08"},      {"exclusion", "matrix"}, {"topological_radius", "3"},
      {"primitive", "triangles"}, {"check", "every_step"}};
  EXPECT_EQ(p, want);
}

TEST(StageKeys, RangesAndTheMethodGateComeFromTheDeclarations) {
  auto error = [](const std::string& table) {
    const auto r = parse(std::string(kCloth) + table);
    return r ? std::string("no error") : r.error().key + " | " + r.error().message;
  };
  EXPECT_EQ(error("[self_collision]\nstiffness = 1e13\n"),
            "self_collision.stiffness | must be in [0, 1e+12] N/m (got 1e+13)");
  EXPECT_EQ(error("[self_collision]\ntopological_radius = 17\n"),
            "self_collision.topological_radius | must be in [0, 16] (got 17)");
  EXPECT_EQ(error("[fields.wind]\ndensity = -1\n"), "fields.wind.density | must be > 0 (got -1)");
  EXPECT_EQ(error("[[obstacle]]\nmethod = \"facets\"\nstiffness = 10\n"),
            "obstacle[0].stiffness | is not used by method = \"facets\" (it is a key of "
            "geometric and conditional)");
  EXPECT_EQ(error("[[obstacle]]\nnormal = \"world\"\nmethod = \"conditional\"\n"),
            "obstacle[0].normal | is not used by method = \"conditional\" (it is a key of "
            "geometric)");
  // Every method-specific key is refused by the other methods, accepted by its own (a mesh with
  // `geometric` has its own message: tests/data/bad/obstacle_mesh_geometric.toml).
  for (const auto& k : obstacle_keys()) {
    if (k.info.methods.empty() || k.key == "mesh") continue;
    for (const auto& m : NameTable<ObstacleMethod>::names) {
      const std::string value = k.key == "normal" ? "\"world\"" : "0.5";
      const std::string e = error("[[obstacle]]\nmethod = \"" + std::string(m.name) + "\"\n" +
                                  std::string(k.key) + " = " + value + "\n");
      EXPECT_EQ(e.find("is not used by method") != std::string::npos, !used_by(k, m.name))
          << k.key << " with " << m.name << ": " << e;
    }
  }
}

// [[contact]] and [simulation.implicit] read their keys from their declarations too: required
// keys, a default taken from another key, ranges, and the resolved values as the stage's
// parameters (which checkpoints' fingerprints hash).
TEST(StageKeys, ContactAndImplicitKeysComeFromTheirDeclarations) {
  const std::string two = R"(
[[flag]]
name = "a"
resolution = [4, 4]
[[flag]]
name = "b"
resolution = [4, 4]
origin = [0, -1, 0]
fixed = "none"
)";
  auto r =
      parse(two + "[[contact]]\nbetween = [\"a\", \"b\"]\nstiffness = 500\nthreshold = 0.05\n");
  ASSERT_TRUE(r) << r.error().to_string();
  ASSERT_EQ(r->model.stages.size(), 1u);
  const std::vector<std::pair<std::string, std::string>> want{
      {"contact[0].between", "a, b"},     {"contact[0].stiffness", "500"},
      {"contact[0].damping", "0"},        {"contact[0].threshold", "0.05"},
      {"contact[0].rest_length", "0.05"}, {"contact[0].method", "broad_phase"}};
  EXPECT_EQ(r->model.stages[0].parameters, want);
  auto error = [&](const std::string& table) {
    const auto e = parse(two + table);
    return e ? std::string("no error") : e.error().key + " | " + e.error().message;
  };
  EXPECT_EQ(error("[[contact]]\nbetween = [\"a\", \"b\"]\nthreshold = 0.05\n"),
            "contact[0].stiffness | is required but missing");
  EXPECT_EQ(error("[[contact]]\nbetween = [\"a\", \"b\"]\nstiffness = 1\nthreshold = 0.05\n"
                  "rest_length = 3e6\n"),
            "contact[0].rest_length | must be in [0, 2e+06] m (got 3e+06)");
  EXPECT_EQ(error("[simulation]\nintegrator = \"implicit_euler\"\n[simulation.implicit]\n"
                  "acceleration = 1\n"),
            "simulation.implicit.acceleration | must be in [0, 0.999999] (got 1)");
  auto s = parse(two +
                 "[simulation]\nintegrator = \"implicit_euler\"\n[simulation.implicit]\n"
                 "solver = \"vbd\"\niterations = 7\nacceleration = 0.5\n");
  ASSERT_TRUE(s) << s.error().to_string();
  EXPECT_EQ(s->settings.implicit.solver, ImplicitSolver::vbd);
  EXPECT_EQ(s->settings.implicit.iterations, 7);
  EXPECT_EQ(s->settings.implicit.acceleration, Real(0.5));
}

// Validation runs without the stage: a self-collision table with no free point and an obstacle
// whose sampling would not fit are refused by the same checks the factories use.
TEST(StageKeys, ValidationIsTheFactoriesCheck) {
  Model m;
  m.points.add(PointKind::fixed, 1, {0, 0, 0}, {});
  m.groups.push_back({"pin", "point", 0, 1});
  SelfCollisionSettings s;
  const StageProblem p = resolve_self_collision(m, s);
  EXPECT_EQ(p.key, "radius");
  EXPECT_EQ(p.message, "self_collision: no free point in the groups");
  EXPECT_THROW(make_self_collision_stage(m, s), std::invalid_argument);
  Obstacle o;
  EXPECT_EQ(check_obstacle(m, o).message, "obstacle 'obstacle': no free point collides with it");
  m.points.add(PointKind::free, 1, {0, 1, 0}, {});
  EXPECT_FALSE(check_obstacle(m, o));
  o.method = ObstacleMethod::conditional;
  o.threshold = Real(1e-6);  // a unit sphere sampled every micrometre: far above the limit
  EXPECT_EQ(check_obstacle(m, o).key, "threshold");
  EXPECT_THROW(make_obstacle_stage(m, o), std::invalid_argument);
}

}  // namespace
