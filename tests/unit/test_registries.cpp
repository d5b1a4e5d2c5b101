// One rule for every registry (link kinds, stage tables, integrators, backends): a second entry
// under a name already registered is a programming error (std::logic_error), never a silent
// replacement.
#include <gtest/gtest.h>

#include "maille/backend.hpp"
#include "maille/integrator.hpp"
#include "maille/link_registry.hpp"
#include "maille/links/spring.hpp"
#include "maille/stage_registry.hpp"

namespace {

using namespace maille;

TEST(Registries, EveryRegistryRefusesASecondEntryUnderOneName) {
  LinkKindRegistry kinds = LinkKindRegistry::with_builtins();
  EXPECT_THROW(kinds.add<Spring>(), std::logic_error);
  StageRegistry stages = StageRegistry::with_builtins();
  EXPECT_THROW(stages.add({"self_collision", false, "again", nullptr}), std::logic_error);
  IntegratorRegistry schemes;
  schemes.add({"mine", "a scheme", nullptr});
  EXPECT_THROW(schemes.add({"mine", "the same name", nullptr}), std::logic_error);
  BackendRegistry backends;
  backends.add({"cpu", "the reference", {}});
  try {
    backends.add({"cpu", "another", {}});
    FAIL() << "accepted";
  } catch (const std::logic_error& e) {
    EXPECT_STREQ(e.what(), "backend registry: 'cpu' is already registered");
  }
}

}  // namespace
