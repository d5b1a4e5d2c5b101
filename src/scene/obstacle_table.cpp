// [[obstacle]] (docs/scene-format.md): one obstacle, a canonical shape or a mesh file, by one of
// three methods. Keys the chosen method does not use are errors naming the key and the method;
// the others keep their defaults, so the viewer can switch the method live (StageSpec::vary).
#include <memory>

#include "maille/geometric_point.hpp"
#include "maille/limits.hpp"
#include "maille/obstacle.hpp"
#include "maille/stage_keys.hpp"
#include "scene_keys.hpp"
#include "stage_tables.hpp"

namespace maille {

namespace {

// motion = { path = "rotate" | "translate" | "oscillate", ... }
ObstacleMotion motion(SceneTable& t, const Vec3& position) {
  ObstacleMotion mo;
  mo.kind = ObstacleMotion::Kind::rotate;  // path's default (a motion table moves)
  // Each path reads its keys (motion_keys(), scene_keys.cpp); another path's key is unknown.
  auto read = [&](std::initializer_list<const char*> keys) {
    for (const char* key : keys) read_key(t, mo, motion_keys(), key);
  };
  read({"path"});
  switch (mo.kind) {
    case ObstacleMotion::Kind::rotate:
      mo.center = position;  // center's default
      read({"axis", "center", "frequency"});
      break;
    case ObstacleMotion::Kind::translate:
      read({"velocity"});
      break;
    case ObstacleMotion::Kind::oscillate:
    case ObstacleMotion::Kind::none:  // not a name: choice() never returns it
      read({"amplitude", "frequency", "phase"});
      break;
  }
  t.finish();
  return mo;
}

void read_placement(SceneTable& t, Obstacle& o) {
  const Vec3 position = t.vec3("position", {0, 0, 0});
  const Vec3 rotation = t.vec3("rotation", {0, 0, 0});
  const Vec3 scale = t.vec3("scale", {1, 1, 1});
  if (!(scale.x > 1e-9 && scale.y > 1e-9 && scale.z > 1e-9))
    t.fail("scale", "every component must be > 1e-9 (M_i divides by it)");
  o.place = shapes::Affine::from(position, rotation, scale);
  if (auto mt = t.child("motion")) o.motion = motion(*mt, position);
}

// The mesh's vertices and triangles (the scene names only the file): a checkpoint taken before
// the file changed is refused.
std::uint64_t mesh_fingerprint(const TriMesh& mesh) {
  std::uint64_t h = 1469598103934665603ull;
  auto bytes = [&](const void* data, std::size_t n) {
    const auto* p = static_cast<const unsigned char*>(data);
    for (std::size_t i = 0; i < n; ++i) h = (h ^ p[i]) * 1099511628211ull;
  };
  bytes(mesh.vertices.data(), mesh.vertices.size() * sizeof(Vec3));
  bytes(mesh.triangles.data(), mesh.triangles.size() * sizeof(mesh.triangles[0]));
  return h;
}

StageSpec spec_of(const Obstacle& o) {
  StageSpec spec{obstacle_stage_name(o), obstacle_phase(o.method),
                 [o](const Model& model) { return make_obstacle_stage(model, o); }};
  spec.variant_option = "method";
  spec.variants = name_strings<ObstacleMethod>();
  if (o.mesh) spec.variants.erase(spec.variants.begin());  // no distance function
  spec.variant = std::string(to_string(o.method));
  visit_keys(obstacle_keys(), o, [&](const StageKey<Obstacle>& k, std::string v) {
    spec.parameters.emplace_back(std::string(k.key), std::move(v));
  });
  if (o.mesh) spec.fingerprint = mesh_fingerprint(*o.mesh);
  spec.vary = [o](const std::string& method) {
    Obstacle other = o;
    other.method = parse_name<ObstacleMethod>(method).value();
    return spec_of(other);
  };
  return spec;
}

}  // namespace

StageSpec obstacle_table(SceneTable& t, const Model& m) {
  Obstacle o;
  // The keys are declared in obstacle_keys(); those read first decide what the others mean.
  const auto keys = obstacle_keys();
  read_key(t, o, keys, "name");
  for (const StageSpec& other : m.stages)
    if (other.name == obstacle_stage_name(o))
      t.fail("name", "another obstacle is named '" + o.name + "'");
  read_key(t, o, keys, "method");
  read_key(t, o, keys, "mesh");
  read_key(t, o, keys, "shape");
  read_placement(t, o);
  // The others: a key the method does not use is refused by name, a shape's own key (tube,
  // top) on another shape too.
  read_keys(t, o, keys, to_string(o.method));
  for (const auto& g : o.collides_with)
    if (!m.group(g)) t.fail("collides_with", "no group named '" + g + "'");
  if (const StageProblem p = check_obstacle(m, o)) t.fail(p.key, p.message);
  return spec_of(o);
}

}  // namespace maille
