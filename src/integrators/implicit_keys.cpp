// [simulation.implicit]'s keys, declared once (stage_keys.hpp). Every key is read whatever the
// solver (the viewer switches solvers live, each keeping its own settings); the methods column
// says which solver uses it.
#include <array>

#include "maille/integrator.hpp"
#include "maille/stage_keys.hpp"

namespace maille {

std::span<const StageKey<ImplicitSettings>> implicit_keys() {
  using I = ImplicitSettings;
  static const std::array<StageKey<I>, 7> keys{
      choice<&I::solver>("solver", {.doc = "CG on link blocks, CG on an assembled Eigen sparse "
                                           "matrix, or vertex block descent (docs/implicit.md)"}),
      number<&I::tolerance>(
          "tolerance", Bound::positive, 0, 0,
          {.methods = "matrix_free, eigen",
           .doc = "CG stops when the residual is below tolerance × the right-hand side's norm"}),
      integer<&I::max_iterations>(
          "max_iterations", 1, 1 << 20,
          {.methods = "matrix_free, eigen", .doc = "CG iterations per solve"}),
      integer<&I::newton_iterations>(
          "newton_iterations", 1, 100,
          {.methods = "matrix_free, eigen", .doc = "linearisations per step (1: Baraff–Witkin)"}),
      integer<&I::iterations>("iterations", 1, 100000,
                              {.methods = "vbd", .doc = "sweeps over every free point per step"}),
      number<&I::acceleration>(
          "acceleration", Bound::non_negative, 0, Real(0.999999),
          {.methods = "vbd",
           .doc = "Chebyshev factor ρ (0: off), with coarse = \"off\" only; turned off for the "
                  "rest of a step when a sweep's merit (sum of g·H⁻¹g) more than doubles"}),
      choice<&I::coarse>(
          "coarse", {.methods = "vbd",
                     .doc = "coarse correction every other sweep: a linear solve over aggregates "
                            "of points (docs/implicit.md), or off"}),
  };
  return keys;
}

}  // namespace maille
