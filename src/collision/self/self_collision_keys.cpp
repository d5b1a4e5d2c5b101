// [self_collision]'s keys, declared once (stage_keys.hpp). The bounds are every link's
// (limits.hpp): beyond them the arithmetic overflows.
#include <array>

#include "maille/limits.hpp"
#include "maille/self_collision.hpp"
#include "maille/stage_keys.hpp"

namespace maille {

std::span<const StageKey<SelfCollisionSettings>> self_collision_keys() {
  using S = SelfCollisionSettings;
  static const std::array<StageKey<S>, 11> keys{
      // Read first: the parser checks the groups against the model before the other keys.
      acted_groups<&S::groups>(
          "groups", {.doc = "which points collide, with themselves and with each other"}),
      number<&S::radius>("radius", Bound::non_negative, 0, limits::max_coordinate,
                         {.unit = "m",
                          .doc = "contact distance s",
                          .default_doc = "half the shortest link among those points",
                          .range_doc = "[0, 1e6] (0: the default)"}),
      number<&S::stiffness>("stiffness", Bound::non_negative, 0, limits::max_stiffness,
                            {.unit = "N/m", .doc = "k of the response"}),
      number<&S::damping>("damping", Bound::non_negative, 0, limits::max_stiffness,
                          {.unit = "N.s/m", .doc = "z of the response (along the contact normal)"}),
      number<&S::friction>("friction", Bound::non_negative, 0, 1e3,
                           {.doc = "μ: a tangential force μ·|F_n| against the relative sliding "
                                   "velocity (viscous below 1 mm/s)"}),
      choice<&S::broad_phase>(
          "broad_phase",
          {.doc = "how candidate pairs are found; all give exactly the same pairs (the GPU "
                  "backend runs its own uniform grid and refuses the others)"}),
      number_or_auto<&S::cell_size>("cell_size", Bound::positive, 0, limits::max_coordinate,
                                    {.unit = "m",
                                     .doc = "grid cell size; `auto`: measured (below)",
                                     .range_doc = "`\"auto\"` or >= radius",
                                     .type_doc = "string or number"}),
      choice<&S::exclusion>("exclusion",
                            {.doc = "how topological neighbours are excluded; `matrix` and "
                                    "`signature` exclude the same pairs"}),
      integer<&S::topological_radius>(
          "topological_radius", 0, 16,
          {.unit = "links",
           .doc = "pairs at graph distance <= R (through every non-conditional link) never "
                  "interact"}),
      choice<&S::primitive>("primitive",
                            {.doc = "`points`: particle-particle contacts; `triangles`: also "
                                    "particle-triangle proximity with the groups' surface faces "
                                    "and edge-edge proximity between their edges (below)"}),
      choice<&S::check>("check",
                        {.doc = "how often the pairs of the groups' faces that cross each other "
                                "are counted (stats.csv `intersecting_pairs`, an exact test); "
                                "`every_step` stops the run (exit 3) at the first"}),
  };
  return keys;
}

}  // namespace maille
