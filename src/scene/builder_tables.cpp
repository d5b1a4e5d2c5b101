#include "builder_tables.hpp"

#include <array>
#include <limits>
#include <stdexcept>

#include "maille/builders.hpp"

namespace maille {

namespace {

constexpr std::int64_t kMaxRes = 1 << 14;

std::uint32_t count(TomlCursor& t, std::string_view key, std::int64_t fallback,
                    std::int64_t min = 2) {
  return static_cast<std::uint32_t>(t.integer(key, fallback, min, kMaxRes));
}

LinkMaterial material(TomlCursor& t, LinkMaterial d) {
  return {t.real("stiffness", d.stiffness, Bound::non_negative),
          t.real("damping", d.damping, Bound::non_negative)};
}

// Builders throw std::invalid_argument for combinations a table check cannot see; report them
// at the table.
template <class F>
Group guarded(TomlCursor& t, F&& build) {
  try {
    return build();
  } catch (const std::invalid_argument& e) {
    t.fail("", e.what());
  }
}

Group flag(TomlCursor& t, Model& m, const std::string& name) {
  FlagParams p;
  p.origin = t.vec3("origin", p.origin);
  p.along = t.vec3("along", p.along);
  p.up = t.vec3("up", p.up);
  p.width = t.real("width", p.width, Bound::positive);
  p.height = t.real("height", p.height, Bound::positive);
  const auto res = t.integers("resolution", {p.nx, p.ny}, 2);
  p.nx = static_cast<std::uint32_t>(res[0]);
  p.ny = static_cast<std::uint32_t>(res[1]);
  p.mass = t.real("mass", p.mass, Bound::positive);
  p.material = material(t, p.material);
  p.shear_stiffness = t.real("shear_stiffness", p.material.stiffness / 2, Bound::non_negative);
  p.bending_stiffness = t.real("bending_stiffness", p.material.stiffness / 10, Bound::non_negative);
  p.fixed = t.text("fixed", p.fixed, {"pole", "corners", "top", "top_corners", "none"});
  return guarded(t, [&] { return build_flag(m, p, name); });
}

Group rope(TomlCursor& t, Model& m, const std::string& name) {
  RopeParams p;
  p.start = t.vec3("start", p.start);
  p.end = t.vec3("end", p.end);
  p.points = count(t, "points", p.points);
  p.mass = t.real("mass", p.mass, Bound::positive);
  p.material = material(t, p.material);
  p.bending_stiffness = t.real("bending_stiffness", p.bending_stiffness, Bound::non_negative);
  p.fixed = t.text("fixed", p.fixed, {"start", "end", "both", "none"});
  return guarded(t, [&] { return build_rope(m, p, name); });
}

Group net(TomlCursor& t, Model& m, const std::string& name) {
  NetParams p;
  p.origin = t.vec3("origin", p.origin);
  p.along = t.vec3("along", p.along);
  p.across = t.vec3("across", p.across);
  p.width = t.real("width", p.width, Bound::positive);
  p.depth = t.real("depth", p.depth, Bound::positive);
  const auto res = t.integers("resolution", {p.nx, p.ny}, 2);
  p.nx = static_cast<std::uint32_t>(res[0]);
  p.ny = static_cast<std::uint32_t>(res[1]);
  p.mass = t.real("mass", p.mass, Bound::positive);
  p.material = material(t, p.material);
  p.fixed = t.text("fixed", p.fixed, {"corners", "ends", "edges", "top", "all", "none"});
  return guarded(t, [&] { return build_net(m, p, name); });
}

Group membrane(TomlCursor& t, Model& m, const std::string& name) {
  MembraneParams p;
  p.center = t.vec3("center", p.center);
  p.normal = t.vec3("normal", p.normal);
  p.radius = t.real("radius", p.radius, Bound::positive);
  p.rings = count(t, "rings", p.rings);
  p.mass = t.real("mass", p.mass, Bound::positive);
  p.material = material(t, p.material);
  p.pretension = t.real("pretension", p.pretension, Bound::non_negative);
  if (p.pretension >= 1) t.fail("pretension", "must be < 1");
  return guarded(t, [&] { return build_membrane(m, p, name); });
}

Group lattice(TomlCursor& t, Model& m, const std::string& name) {
  LatticeParams p;
  p.origin = t.vec3("origin", p.origin);
  p.size = t.vec3("size", p.size);
  if (!(p.size.x > 0 && p.size.y > 0 && p.size.z > 0)) t.fail("size", "must be > 0 on every axis");
  const auto res = t.integers("resolution", {5, 5, 5}, 2);
  p.resolution = {static_cast<std::uint32_t>(res[0]), static_cast<std::uint32_t>(res[1]),
                  static_cast<std::uint32_t>(res[2])};
  p.shape = t.text("shape", p.shape, {"box", "ball"});
  p.mass = t.real("mass", p.mass, Bound::positive);
  p.material = material(t, p.material);
  p.shear_stiffness = t.real("shear_stiffness", p.material.stiffness / 2, Bound::non_negative);
  p.velocity = t.vec3("velocity", p.velocity);
  p.fixed = t.text("fixed", p.fixed, {"none", "bottom"});
  return guarded(t, [&] { return build_lattice(m, p, name); });
}

Group floor(TomlCursor& t, Model& m, const std::string& name) {
  FloorParams p;
  p.center = t.vec3("center", p.center);
  p.width = t.real("width", p.width, Bound::positive);
  p.depth = t.real("depth", p.depth, Bound::positive);
  const auto res = t.integers("resolution", {p.nx, p.nz}, 2);
  p.nx = static_cast<std::uint32_t>(res[0]);
  p.nz = static_cast<std::uint32_t>(res[1]);
  return guarded(t, [&] { return build_floor(m, p, name); });
}

constexpr std::array<BuilderTable, 6> kTables{{
    {"flag", flag},
    {"rope", rope},
    {"net", net},
    {"membrane", membrane},
    {"lattice", lattice},
    {"floor", floor},
}};

}  // namespace

std::span<const BuilderTable> builder_tables() {
  return kTables;
}

}  // namespace maille
