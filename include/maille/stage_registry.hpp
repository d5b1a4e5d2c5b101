// Scene table -> stage. A feature that plugs into the step (self-collision, obstacles) registers
// the table that configures it; the scene reader parses that table with the factory and keeps
// the resulting StageSpec in the Model, and every Simulator built from the model installs it.
// So `maille run`, `maille render`, the viewer and the tests get the stage with no wiring in the
// apps, and a program (or a test) adds its own tables beside the built-ins.
#pragma once

#include <functional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "maille/model.hpp"
#include "maille/scene_table.hpp"
#include "maille/stage.hpp"

namespace maille {

class StageRegistry {
 public:
  struct Entry {
    std::string table;        // scene key: [table] (one) or [[table]] (an array of them)
    bool array = false;       // true for [[table]]
    std::string description;  // one line, for docs and `maille info`
    // Reads the table (errors through table.fail) against the finished model and returns the
    // stage to install. Called once per table (per element for arrays).
    std::function<StageSpec(SceneTable& table, const Model& model)> parse;
  };

  void add(Entry e) { entries_.push_back(std::move(e)); }
  const Entry* find(std::string_view table) const;
  std::span<const Entry> entries() const { return entries_; }

  // The stages the engine itself provides (empty until the collision themes land).
  static StageRegistry with_builtins();

 private:
  std::vector<Entry> entries_;
};

}  // namespace maille
