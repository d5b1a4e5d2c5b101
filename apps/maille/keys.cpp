// `maille info --keys`: every declared scene table's keys, as docs/scene-format.md shows them
// (the declarations are the source; unit.StageKeys.* checks the docs against them), and every
// named choice's names.
#include <iostream>

#include "commands.hpp"
#include "maille/audio.hpp"
#include "maille/backend.hpp"
#include "maille/builders.hpp"
#include "maille/integrator.hpp"
#include "maille/io.hpp"
#include "maille/obstacle.hpp"
#include "maille/self_collision.hpp"
#include "maille/stage_registry.hpp"

namespace maille::app {

namespace {

template <Named E>
void choice_line(std::ostream& out) {
  out << "- " << NameTable<E>::what << ": " << name_list<E>() << '\n';
}

}  // namespace

int describe_keys() {
  for (const DeclaredTable& t : declared_tables(StageRegistry::with_builtins())) {
    std::cout << "## " << t.table << ": " << t.description << "\n\n";
    for (const std::string& line : markdown_table(t)) std::cout << line << '\n';
    std::cout << '\n';
  }
  std::cout << "## Named choices\n\n";
  choice_line<BroadPhase>(std::cout);
  choice_line<Exclusion>(std::cout);
  choice_line<Primitive>(std::cout);
  choice_line<ObstacleMethod>(std::cout);
  choice_line<ShapeKind>(std::cout);
  choice_line<FlagFixed>(std::cout);
  choice_line<RopeFixed>(std::cout);
  choice_line<NetFixed>(std::cout);
  choice_line<LatticeFixed>(std::cout);
  choice_line<LatticeShape>(std::cout);
  choice_line<BackendKind>(std::cout);
  choice_line<ImplicitSolver>(std::cout);
  choice_line<FrameFormat>(std::cout);
  choice_line<audio::Quantity>(std::cout);
  choice_line<audio::SampleFormat>(std::cout);
  choice_line<audio::Resampler>(std::cout);
  return 0;
}

}  // namespace maille::app
