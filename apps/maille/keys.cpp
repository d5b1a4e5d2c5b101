// `maille info --keys`: every declared scene table's keys, as docs/scene-format.md shows them
// (the declarations are the source; unit.StageKeys.* checks the docs against them), and every
// named choice's names.
#include <fstream>
#include <iostream>
#include <sstream>

#include "commands.hpp"
#include "maille/audio.hpp"
#include "maille/backend.hpp"
#include "maille/builders.hpp"
#include "maille/exit_codes.hpp"
#include "maille/integrator.hpp"
#include "maille/io.hpp"
#include "maille/obstacle.hpp"
#include "maille/self_collision.hpp"
#include "maille/stage_registry.hpp"

namespace maille::app {

namespace {

// One line per enum: "- what: a, b, c".
template <Named... E>
void choice_lines(std::ostream& out) {
  ((out << "- " << NameTable<E>::what << ": " << name_list<E>() << '\n'), ...);
}

// Rewrites the key tables of `path` (those after a `<!-- keys: TABLE -->` line); prose is kept.
int update_docs(const std::string& path, const std::vector<DeclaredTable>& tables) {
  std::ifstream in(path, std::ios::binary);
  if (!in) {
    std::cerr << path << ": cannot open the file\n";
    return exit_code::bad_input;
  }
  std::stringstream text;
  text << in.rdbuf();
  std::string updated;
  try {
    updated = with_declared_tables(text.str(), tables);
  } catch (const std::invalid_argument& e) {
    std::cerr << path << ": " << e.what() << '\n';
    return exit_code::bad_input;
  }
  if (updated == text.str()) return 0;
  try {  // whole or not at all: the docs are never left half written
    AtomicFile out(path);
    out.stream() << updated;
    out.commit();
  } catch (const std::runtime_error& e) {
    std::cerr << e.what() << '\n';
    return exit_code::output_error;
  }
  std::cout << path << ": key tables updated\n";
  return 0;
}

}  // namespace

int describe_keys(const std::string& docs) {
  const auto tables = declared_tables(StageRegistry::with_builtins());
  if (!docs.empty()) return update_docs(docs, tables);
  for (const DeclaredTable& t : tables) {
    std::cout << "## " << t.table << ": " << t.description << "\n\n";
    std::cout << key_table_marker(t) << '\n';
    for (const std::string& line : markdown_table(t)) std::cout << line << '\n';
    std::cout << '\n';
  }
  std::cout << "## Named choices\n\n";
  choice_lines<BroadPhase, Exclusion, Primitive, ObstacleMethod>(std::cout);
  std::cout << "- shape: " << shape_name_list() << '\n';  // the shape table's rows
  choice_lines<FlagFixed, RopeFixed, NetFixed, LatticeFixed, LatticeShape, BackendKind,
               ImplicitSolver, FrameFormat, audio::Quantity, audio::SampleFormat, audio::Resampler>(
      std::cout);
  return 0;
}

}  // namespace maille::app
