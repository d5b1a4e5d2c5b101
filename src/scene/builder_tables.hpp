// The scene keywords of the builders: [[flag]], [[rope]], ... Each reads its table into the
// builder's parameters and builds. Adding a builder: one entry here and one file with the build.
#pragma once

#include <span>
#include <string>
#include <string_view>

#include "maille/model.hpp"
#include "toml_cursor.hpp"

namespace maille {

struct BuilderTable {
  std::string_view keyword;
  Group (*build)(TomlCursor& table, Model& m, const std::string& name);
};
std::span<const BuilderTable> builder_tables();

}  // namespace maille
