// [[obstacle]]'s keys, declared once (stage_keys.hpp), with the methods that use each: a key the
// chosen method does not use is an error naming the key and the method (the scene reader's
// gate), and the others keep their defaults so that the viewer can switch the method live.
#include <array>

#include "maille/geometric_point.hpp"
#include "maille/limits.hpp"
#include "maille/obstacle.hpp"
#include "maille/stage_keys.hpp"

namespace maille {

namespace {

std::string number(Real v) {
  return key_detail::number_text(double(v));
}

// Rotation and scale resolve to one matrix, M_d = R S: the scale key shows its rows for both.
std::string direct_map(const Obstacle& o) {
  std::string out = "M_d";
  for (const auto& row : o.place.direct.m)
    out.append(" ").append(key_detail::vector_text({row[0], row[1], row[2]}));
  return out;
}

// The motion's resolved fields (all of them: a fingerprint must see any change).
std::string motion_text(const Obstacle& o) {
  const ObstacleMotion& m = o.motion;
  if (!m.moves()) return "none";
  using key_detail::vector_text;
  std::string out(to_string(m.kind));
  out.append(" axis ").append(vector_text(m.axis)).append(" center ").append(vector_text(m.center));
  out.append(" velocity ").append(vector_text(m.velocity));
  out.append(" amplitude ").append(vector_text(m.amplitude));
  out.append(" frequency ").append(number(m.frequency)).append(" phase ").append(number(m.phase));
  return out;
}

}  // namespace

std::span<const StageKey<Obstacle>> obstacle_keys() {
  using O = Obstacle;
  static const std::array<StageKey<O>, 20> keys{
      custom<O>("name", KeyType::text,
                {.doc = "names the stage (`obstacle:NAME`) and its stats columns",
                 .default_doc = "`\"obstacle\"`",
                 .range_doc = "letters, digits, `_`, `-`; unique"},
                [](const O& o) { return o.name; }),
      parsed_choice<&O::method>("method", {.doc = "how the obstacle acts (above)"}),
      parsed_choice<&O::shape>(
          "shape", {.doc = "canonical shapes of unit size: sphere radius 1; cube [-1,1]³; "
                           "cylinder, cone and capsule along y, radius 1, y from -1 to 1; torus "
                           "about y, major radius 1; plane: the half-space y <= 0 for "
                           "`geometric`, the square [-1,1]×{0}×[-1,1] (normal +y) otherwise"}),
      custom<O>("mesh", KeyType::text,
                {.methods = "facets, conditional",
                 .doc = "instead of `shape`: a mesh file, relative to the scene file "
                        "([meshes.md](meshes.md)); errors name the file and line",
                 .default_doc = "none",
                 .range_doc = "an OBJ or STL file"},
                [](const O& o) { return o.mesh ? o.mesh_file : std::string("none"); }),
      custom<O>("position", KeyType::vector,
                {.unit = "m", .doc = "translation t", .default_doc = "`[0, 0, 0]`"},
                [](const O& o) { return key_detail::vector_text(o.place.translation); }),
      custom<O>("rotation", KeyType::vector,
                {.unit = "degrees",
                 .doc = "about x, then y, then z (world axes: R = Rz Ry Rx)",
                 .default_doc = "`[0, 0, 0]`"}),
      custom<O>("scale", KeyType::vector,
                {.doc = "S, applied first: M_d = R S, M_i = S⁻¹ Rᵀ",
                 .default_doc = "`[1, 1, 1]`",
                 .range_doc = "> 1e-9 each"},
                direct_map),
      number<&O::tube>("tube", Bound::positive, 0, 1,
                       {.doc = "torus only: tube radius / major radius", .range_doc = "(0, 1]"}),
      number<&O::top>(
          "top", Bound::non_negative, 0, 1,
          {.doc = "cone only: top radius / bottom radius (0: pointed)", .range_doc = "[0, 1]"}),
      integer<&O::resolution>(
          "resolution", 8, 512,
          {.doc = "segments around curved shapes when tessellated (facets, conditional, "
                  "drawing)"}),
      number<&O::stiffness>("stiffness", Bound::non_negative, 0, limits::max_stiffness,
                            {.unit = "N/m",
                             .methods = "geometric, conditional",
                             .doc = "k: under a uniform scale a resting particle sinks m g / k "
                                    "(geometric)"}),
      number<&O::damping>("damping", Bound::non_negative, 0, limits::max_stiffness,
                          {.unit = "N.s/m",
                           .methods = "geometric, conditional",
                           .doc = "z, on the velocity relative to the surface"}),
      number<&O::friction>(
          "friction", Bound::non_negative, 0, 100,
          {.methods = "geometric",
           .doc = "μ: Coulomb friction μ F_n against the sliding velocity relative to the "
                  "surface, viscous below 1 mm/s; implicit Euler (vbd) holds F_n and the normal "
                  "from the step's start (lagged friction)"}),
      custom<O>("normal", KeyType::text,
                {.methods = "geometric",
                 .doc = "`canonical`: the canonical mapping (k times the world image of the "
                        "canonical penetration; under a non-uniform scale it leans off the "
                        "surface normal); `world`: along the world normal with the world depth",
                 .default_doc = "`\"canonical\"`",
                 .range_doc = "`canonical`, `world`"},
                [](const O& o) {
                  return std::string(
                      to_string(o.world_normal ? ContactNormal::world : ContactNormal::canonical));
                }),
      number<&O::threshold>("threshold", Bound::positive, 0, limits::max_coordinate,
                            {.unit = "m",
                             .methods = "conditional",
                             .doc = "contact distance of the sampled points, and their spacing"}),
      number<&O::alpha>("alpha", Bound::non_negative, 0, 1,
                        {.methods = "facets",
                         .doc = "dissipation: the restitution of the normal velocity (0: stops, "
                                "1: elastic)"}),
      number<&O::beta>("beta", Bound::non_negative, 0, 1,
                       {.methods = "facets",
                        .doc = "friction: Coulomb's coefficient (sticks while tan θ < β on an "
                               "incline)"}),
      number<&O::epsilon>("epsilon", Bound::positive, 0, 1,
                          {.unit = "m",
                           .methods = "facets",
                           .doc = "the facet tolerance ε: \"above a facet\" means N·AP > ε"}),
      custom<O>("collides_with", KeyType::texts,
                {.doc = "which free points collide with the obstacle",
                 .default_doc = "every free point",
                 .range_doc = "groups"},
                [](const O& o) {
                  std::string out;
                  for (const auto& g : o.collides_with)
                    out.append(out.empty() ? "" : ",").append(g);
                  return out.empty() ? std::string("every free point") : out;
                }),
      custom<O>("motion", KeyType::table,
                {.doc = "a scripted rigid motion, below", .default_doc = "none"}, motion_text),
  };
  return keys;
}

}  // namespace maille
