#include "maille/model.hpp"

#include <vector>

namespace maille {

const Group* Model::group(const std::string& name) const {
  for (const auto& g : groups)
    if (g.name == name) return &g;
  return nullptr;
}

void Model::prepare() {
  links.prepare(points.size());
  // Faces are coloured like links so that the wind pass scatters to corners without races.
  std::vector<std::uint32_t> idx;
  idx.reserve(surface.triangles.size() * 3);
  for (const auto& t : surface.triangles) idx.insert(idx.end(), t.begin(), t.end());
  Colouring c = colour_elements(idx, 3, points.size());
  std::vector<std::array<std::uint32_t, 3>> sorted(surface.triangles.size());
  for (std::size_t i = 0; i < c.order.size(); ++i) sorted[i] = surface.triangles[c.order[i]];
  surface.triangles = std::move(sorted);
  surface.colour_offsets = std::move(c.offsets);
}

}  // namespace maille
