// [[contact]]'s keys, declared once (stage_keys.hpp). Every key is used by both methods; the
// bounds are the engine's stiffness and coordinate limits (limits.hpp), as for [[link]].
#include <array>

#include "maille/group_contact.hpp"
#include "maille/limits.hpp"
#include "maille/stage_keys.hpp"

namespace maille {

std::span<const StageKey<GroupContactSpec>> contact_keys() {
  using C = GroupContactSpec;
  static const std::array<StageKey<C>, 6> keys{
      custom<C>("between", KeyType::texts,
                {.doc = "e.g. `[\"cube\", \"floor\"]`",
                 .default_doc = "required",
                 .range_doc = "two different groups",
                 .type_doc = "array of 2 strings"},
                [](const C& c) { return c.a + ", " + c.b; }),
      number<&C::stiffness>("stiffness", Bound::non_negative, 0, limits::max_stiffness,
                            {.unit = "N/m", .doc = "k", .required = true}),
      number<&C::damping>("damping", Bound::non_negative, 0, limits::max_stiffness,
                          {.unit = "N.s/m", .doc = "z"}),
      number<&C::threshold>(
          "threshold", Bound::positive, 0, 2 * limits::max_coordinate,
          {.unit = "m",
           .doc = "s; against a grid of points spaced d, keep s > d/√2",
           .required = true}),
      number_from<&C::rest_length>("rest_length", Bound::non_negative, 0,
                                   2 * limits::max_coordinate,
                                   [](const C& c) { return c.threshold; },
                                   {.unit = "m", .doc = "L0", .default_doc = "the threshold"}),
      choice<&C::method>("method", {.doc = "how pairs are found: a grid each step, or one stored "
                                           "link per pair"}),
  };
  return keys;
}

}  // namespace maille
