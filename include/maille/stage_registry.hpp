// Scene table -> stage. A feature that plugs into the step (self-collision, obstacles) registers
// the table that configures it; the scene reader parses that table with the factory and keeps
// the resulting StageSpec in the Model, and every Simulator built from the model installs it.
// So `maille run`, `maille render`, the viewer and the tests get the stage with no wiring in the
// apps, and a program (or a test) adds its own tables beside the built-ins.
#pragma once

#include <functional>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "maille/model.hpp"
#include "maille/registry.hpp"
#include "maille/scene_table.hpp"
#include "maille/stage.hpp"
#include "maille/stage_keys.hpp"

namespace maille {

class LinkKindRegistry;

struct StageTableEntry {
  std::string table{};        // scene key: [table] (one) or [[table]] (an array of them)
  bool array = false;         // true for [[table]]
  std::string description{};  // one line, for docs and `maille info`
  // Reads the table (errors through table.fail) against the finished model and returns the
  // stage to install. Called once per table (per element for arrays).
  std::function<StageSpec(SceneTable& table, const Model& model)> parse{};
  // The table's keys (stage_keys.hpp: describe_keys), for `maille info --keys` and the docs.
  std::vector<KeyInfo> keys{};
  // Instead of `parse`, for an array whose elements make one stage together ([[contact]]: every
  // broad-phase table one stage): called once with all of them (none: not called), it returns
  // the stage, or none when no element asks for one. It may add bricks to the model (a
  // [[contact]] by links adds its conditional links): gathered tables are read before the
  // others, in the order of registration, right after the model's own bricks.
  std::function<std::optional<StageSpec>(std::span<SceneTable* const> tables, Model& model)>
      gather{};
  // The stage its tables make (stage.hpp: name and phase, said once beside the stage): `maille
  // info` lists it, and the scene reader refuses a StageSpec named otherwise (a program's entry
  // may leave it empty). For an array whose elements each make a stage ([[obstacle]]), `name`
  // is the prefix of theirs ("obstacle:" + the element's name) and `phase` the default method's
  // (an element may choose a method of another phase).
  StageInfo stage{};
  // The entry's elements are the [[link]] tables whose kind is `table` (a link keyword that
  // makes a stage rather than link bricks: "geometric_contact"), gathered (`gather`) after the
  // model's links.
  bool of_links = false;
};

// add() throws std::logic_error for a table already registered (names.hpp: registered_twice).
class StageRegistry : public Registry<StageTableEntry, &StageTableEntry::table> {
 public:
  using Entry = StageTableEntry;
  StageRegistry() : Registry("stage registry") {}

  // The stages the engine itself provides: self-collision, obstacles, [[contact]] and the rest.
  static StageRegistry with_builtins();
};

// A scene table whose keys are declared (stage_keys.hpp), as `maille info --keys` and the docs
// show it: "[self_collision]", "[[obstacle]]", "[fields.wind]".
struct DeclaredTable {
  std::string table;
  std::string description;
  std::vector<KeyInfo> keys;
  bool methods = false;        // some key is used by some methods only: a "methods" column
  std::string group_column{};  // a first column ("kind": KeyInfo::group), or none
  std::string page = "scene-format.md";  // the docs page (docs/) that holds its table
};
// Every table a scene file may hold, in docs/scene-format.md's order: the scene's own tables
// (src/scene/scene_keys.cpp), the link kinds' fields (of `kinds`), sound, the registry's stage
// tables, the bricks and the builders (src/scene/builder_keys.cpp); then the sweep file's keys
// (page sweep.md).
std::vector<DeclaredTable> declared_tables(const StageRegistry& stages,
                                           const LinkKindRegistry& kinds);
std::vector<DeclaredTable> declared_tables(const StageRegistry& stages);  // built-in kinds
// The table's markdown: the header line, the separator, one row per key (docs/scene-format.md).
std::vector<std::string> markdown_table(const DeclaredTable& t);
// The line that stands before a table's generated rows in the docs: "<!-- keys: [scene] -->".
std::string key_table_marker(const DeclaredTable& t);
// `doc` with the table after each marker replaced by the declared one (prose is kept as is);
// throws std::invalid_argument for a marker that names no table of `tables`.
std::string with_declared_tables(std::string_view doc, std::span<const DeclaredTable> tables);

}  // namespace maille
