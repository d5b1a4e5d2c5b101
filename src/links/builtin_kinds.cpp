// The built-in link kinds, registered like any other: this file is the only list of them.
#include "maille/link_registry.hpp"
#include "maille/links/conditional.hpp"
#include "maille/links/damper.hpp"
#include "maille/links/friction.hpp"
#include "maille/links/spring.hpp"
#include "maille/links/spring_damper.hpp"

namespace maille {

LinkKindRegistry LinkKindRegistry::with_builtins() {
  LinkKindRegistry r;
  r.add<Spring>();
  r.add<Damper>();
  r.add<SpringDamper>();
  r.add<ConditionalSpringDamper>();
  r.add<Friction>();
  return r;
}

}  // namespace maille
