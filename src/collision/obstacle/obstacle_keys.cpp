// [[obstacle]]'s keys, declared once (stage_keys.hpp), with the methods that use each: a key the
// chosen method does not use is an error naming the key and the method (the scene reader's
// gate), and the others keep their defaults so that the viewer can switch the method live.
#include <array>
#include <filesystem>
#include <iterator>
#include <memory>
#include <vector>

#include "maille/geometric_point.hpp"
#include "maille/limits.hpp"
#include "maille/mesh.hpp"
#include "maille/obstacle.hpp"
#include "maille/shape_keys.hpp"
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

// mesh = "FILE": read relative to the scene file, for the methods with facets only.
void read_mesh_key(SceneTable& t, Obstacle& o, const StageKey<Obstacle>& k) {
  if (!t.has(k.key)) return;
  if (t.has("shape")) t.fail(k.key, "give either shape or mesh, not both");
  const std::string file = t.text(k.key, "");
  if (file.find('\0') != std::string::npos) t.fail(k.key, "the path contains a NUL byte");
  const std::filesystem::path where = std::filesystem::path(t.file()).parent_path() / file;
  try {
    o.mesh = std::make_shared<const TriMesh>(read_mesh(where.string()));
  } catch (const MeshError& e) {
    t.fail(k.key, e.what());
  }
  o.mesh_file = where.string();
  if (o.method == ObstacleMethod::geometric)
    t.fail(k.key,
           "a mesh has no canonical distance function: use method = \"facets\" or "
           "\"conditional\"");
}

// Where an obstacle holds its shape (shape_keys.hpp): none with a mesh.
struct ObstacleShape {
  static auto& kind(auto& o) { return o.shape; }
  static auto& parameter(auto& o) { return o.shape_parameter; }
  static bool canonical(const Obstacle& o) { return !o.mesh; }
};

// The keys up to the placement, the shapes' parameters (shape_keys.hpp), the rest.
std::vector<StageKey<Obstacle>> declared_keys() {
  using O = Obstacle;
  std::vector<StageKey<O>> keys{
      // Read first, then its uniqueness among the model's stages (obstacle_table.cpp).
      stage_name<&O::name>({.doc = "names the stage (`obstacle:NAME`) and its stats columns",
                            .default_doc = "`\"obstacle\"`"}),
      // The method, then the mesh, then the shape are read first: they decide the other keys.
      parsed_choice<&O::method>("method", {.doc = "how the obstacle acts (above)"}),
      only_if(
          read_first(shape_key<O, ObstacleShape>({.doc = shape_docs()})),
          [](const O& o) { return !o.mesh; }, "give either shape or mesh, not both"),
      read_first(parsed<O>("mesh", KeyType::text,
                           {.methods = "facets, conditional",
                            .doc = "instead of `shape`: a mesh file, relative to the scene file "
                                   "([meshes.md](meshes.md)); errors name the file and line",
                            .default_doc = "none",
                            .range_doc = "an OBJ or STL file"},
                           read_mesh_key,
                           [](const O& o) { return o.mesh ? o.mesh_file : std::string("none"); })),
      // The placement resolves into one map (Obstacle::place, no member per key): the parser
      // reads the three keys together (obstacle_table.cpp).
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
  };
  for (auto& k : shape_parameter_keys<O, ObstacleShape>()) keys.push_back(k);
  const StageKey<O> rest[] = {
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
      // A named choice kept as a flag (Obstacle::world_normal).
      parsed<O>(
          "normal", KeyType::text,
          {.methods = "geometric",
           .doc = "`canonical`: the canonical mapping (k times the world image of the "
                  "canonical penetration; under a non-uniform scale it leans off the "
                  "surface normal); `world`: along the world normal with the world depth",
           .default_doc = "`\"canonical\"`",
           .range_doc = "`canonical`, `world`"},
          [](SceneTable& t, O& o, const StageKey<O>& k) {
            o.world_normal = t.choice(k.key, ContactNormal::canonical) == ContactNormal::world;
          },
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
      texts<&O::collides_with>("collides_with",
                               {.doc = "which free points collide with the obstacle",
                                .default_doc = "every free point",
                                .range_doc = "groups"},
                               [](const O& o) {
                                 std::string out;
                                 for (const auto& g : o.collides_with)
                                   out.append(out.empty() ? "" : ",").append(g);
                                 return out.empty() ? std::string("every free point") : out;
                               }),
      // A sub-table with keys of its own (motion_keys(), the scene library's), read with the
      // placement by the parser (its center defaults to the position).
      custom<O>("motion", KeyType::table,
                {.doc = "a scripted rigid motion, below", .default_doc = "none"}, motion_text),
  };
  keys.insert(keys.end(), std::begin(rest), std::end(rest));
  return keys;
}

}  // namespace

std::span<const StageKey<Obstacle>> obstacle_keys() {
  static const std::vector<StageKey<Obstacle>> keys = declared_keys();
  return keys;
}

}  // namespace maille
