// The accordion-folded cloth of the self-collision tests, benchmarks and study.
#include <cmath>

#include "maille/builders.hpp"

namespace maille {

Group build_crumpled_cloth(Model& m, const CrumpledClothParams& p, const std::string& name) {
  FlagParams f;
  f.nx = p.n;
  f.ny = p.n;
  f.width = p.size;
  f.height = p.size;
  f.fixed = FlagFixed::none;
  const Group g = build_flag(m, f, name);
  const Real spacing = p.size / Real(p.n - 1);
  const Real fold = Real(std::max<std::uint32_t>(p.fold, 1));
  for (std::uint32_t k = g.first; k < g.first + g.count; ++k) {
    Vec3& x = m.points.initial_position[k];
    const Real u = x.x / spacing;  // column index
    const Real layer = std::floor(u / fold);
    const Real t = u - fold * layer;  // position inside the layer
    const bool forward = std::fmod(layer, Real(2)) == 0;
    const Real v = x.y / spacing;
    x = {(forward ? t : fold - t) * spacing, x.y,
         (layer * p.gap + p.wave * std::sin(v * Real(0.7))) * spacing};
  }
  return g;
}

}  // namespace maille
