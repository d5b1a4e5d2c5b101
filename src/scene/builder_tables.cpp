#include "builder_tables.hpp"

#include <array>
#include <limits>
#include <stdexcept>

#include "maille/builders.hpp"
#include "maille/limits.hpp"

namespace maille {

namespace {

constexpr std::int64_t kMaxRes = 1 << 14;

std::uint32_t count(TomlCursor& t, std::string_view key, std::int64_t fallback,
                    std::int64_t min = 2) {
  return static_cast<std::uint32_t>(t.integer(key, fallback, min, kMaxRes));
}

// Physical bounds (maille/limits.hpp): a stiffness or damping within 1e12, a length within the
// +-1e6 m box, a total mass of at least 1e-12 kg.
Real stiffness(TomlCursor& t, std::string_view key, Real fallback) {
  const Real k = t.real(key, fallback, Bound::non_negative);
  t.check_range(key, k, 0, limits::max_stiffness,
                key.find("damping") != key.npos ? "N.s/m" : "N/m");
  return k;
}

Real length(TomlCursor& t, std::string_view key, Real fallback) {
  const Real l = t.real(key, fallback, Bound::positive);
  t.check_range(key, l, 0, 2 * limits::max_coordinate, "m");
  return l;
}

Real mass(TomlCursor& t, Real fallback) {
  const Real kg = t.real("mass", fallback, Bound::positive);
  t.check_range("mass", kg, limits::min_mass, limits::max_mass, "kg");
  return kg;
}

LinkMaterial material(TomlCursor& t, LinkMaterial d) {
  return {stiffness(t, "stiffness", d.stiffness), stiffness(t, "damping", d.damping)};
}

// Saturating product of counts: a resolution of 2^28 per axis must not wrap around.
std::uint64_t times(std::uint64_t a, std::uint64_t b) {
  constexpr std::uint64_t top = std::numeric_limits<std::uint64_t>::max();
  return a != 0 && b > top / a ? top : a * b;
}

// Refuses, at `key`, a builder whose points and links would not fit next to the model's: checked
// before anything is allocated. Estimates are upper bounds for the builder.
void budget(TomlCursor& t, std::string_view key, const Model& m, std::uint64_t points,
            std::uint64_t links, std::uint64_t faces) {
  limits::SizeEstimate total{m.points.size(), m.links.total(), m.surface.triangles.size()};
  const std::uint64_t top = std::numeric_limits<std::uint64_t>::max();
  total.points = points > top - total.points ? top : total.points + points;
  total.links = links > top - total.links ? top : total.links + links;
  total.faces = faces > top - total.faces ? top : total.faces + faces;
  if (const std::string why = limits::check_size(total); !why.empty()) t.fail(key, why);
}

constexpr std::int64_t kMaxAxis = std::int64_t{limits::max_points};

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
  p.width = length(t, "width", p.width);
  p.height = length(t, "height", p.height);
  const auto res = t.integers("resolution", {p.nx, p.ny}, 2, kMaxAxis);
  const std::uint64_t n = times(std::uint64_t(res[0]), std::uint64_t(res[1]));
  budget(t, "resolution", m, n, times(n, 6), times(n, 2));  // structural, shear, bending
  p.nx = static_cast<std::uint32_t>(res[0]);
  p.ny = static_cast<std::uint32_t>(res[1]);
  p.mass = mass(t, p.mass);
  p.material = material(t, p.material);
  p.shear_stiffness = stiffness(t, "shear_stiffness", p.material.stiffness / 2);
  p.bending_stiffness = stiffness(t, "bending_stiffness", p.material.stiffness / 10);
  p.fixed = t.choice("fixed", p.fixed);
  return guarded(t, [&] { return build_flag(m, p, name); });
}

Group rope(TomlCursor& t, Model& m, const std::string& name) {
  RopeParams p;
  p.start = t.vec3("start", p.start);
  p.end = t.vec3("end", p.end);
  p.points = count(t, "points", p.points);
  budget(t, "points", m, p.points, 2 * std::uint64_t(p.points), 0);
  p.mass = mass(t, p.mass);
  p.material = material(t, p.material);
  p.bending_stiffness = stiffness(t, "bending_stiffness", p.bending_stiffness);
  p.fixed = t.choice("fixed", p.fixed);
  p.pretension = t.real("pretension", p.pretension, Bound::non_negative);
  if (p.pretension >= 1) t.fail("pretension", "must be < 1");
  return guarded(t, [&] { return build_rope(m, p, name); });
}

Group net(TomlCursor& t, Model& m, const std::string& name) {
  NetParams p;
  p.origin = t.vec3("origin", p.origin);
  p.along = t.vec3("along", p.along);
  p.across = t.vec3("across", p.across);
  p.width = length(t, "width", p.width);
  p.depth = length(t, "depth", p.depth);
  const auto res = t.integers("resolution", {p.nx, p.ny}, 2, kMaxAxis);
  const std::uint64_t n = times(std::uint64_t(res[0]), std::uint64_t(res[1]));
  budget(t, "resolution", m, n, times(n, 2), 0);
  p.nx = static_cast<std::uint32_t>(res[0]);
  p.ny = static_cast<std::uint32_t>(res[1]);
  p.mass = mass(t, p.mass);
  p.material = material(t, p.material);
  p.fixed = t.choice("fixed", p.fixed);
  p.pretension = t.real("pretension", p.pretension, Bound::non_negative);
  if (p.pretension >= 1) t.fail("pretension", "must be < 1");
  return guarded(t, [&] { return build_net(m, p, name); });
}

Group membrane(TomlCursor& t, Model& m, const std::string& name) {
  MembraneParams p;
  p.center = t.vec3("center", p.center);
  p.normal = t.vec3("normal", p.normal);
  p.radius = length(t, "radius", p.radius);
  p.rings = count(t, "rings", p.rings);
  {  // lattice points in the disk: about (2 pi / sqrt 3) rings^2; 3 links and 2 faces each
    const std::uint64_t r = std::uint64_t(p.rings) + 2;
    const std::uint64_t n = times(times(r, r), 4);
    budget(t, "rings", m, n, times(n, 3), times(n, 2));
  }
  p.mass = mass(t, p.mass);
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
  const auto res = t.integers("resolution", {5, 5, 5}, 2, kMaxAxis);
  {  // 3 structural, 6 face-diagonal and 4 body-diagonal links per point; outer faces
    const std::uint64_t n =
        times(times(std::uint64_t(res[0]), std::uint64_t(res[1])), std::uint64_t(res[2]));
    budget(t, "resolution", m, n, times(n, 13), times(n, 2));
  }
  p.resolution = {static_cast<std::uint32_t>(res[0]), static_cast<std::uint32_t>(res[1]),
                  static_cast<std::uint32_t>(res[2])};
  p.shape = t.choice("shape", p.shape);
  p.mass = mass(t, p.mass);
  p.material = material(t, p.material);
  p.shear_stiffness = stiffness(t, "shear_stiffness", p.material.stiffness / 2);
  p.velocity = t.vec3("velocity", p.velocity);
  p.fixed = t.choice("fixed", p.fixed);
  return guarded(t, [&] { return build_lattice(m, p, name); });
}

Group floor(TomlCursor& t, Model& m, const std::string& name) {
  FloorParams p;
  p.center = t.vec3("center", p.center);
  p.width = length(t, "width", p.width);
  p.depth = length(t, "depth", p.depth);
  const auto res = t.integers("resolution", {p.nx, p.nz}, 2, kMaxAxis);
  budget(t, "resolution", m, times(std::uint64_t(res[0]), std::uint64_t(res[1])), 0, 0);
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
