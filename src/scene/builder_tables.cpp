#include "builder_tables.hpp"

#include <array>
#include <limits>
#include <stdexcept>

#include "builder_keys.hpp"
#include "maille/builders.hpp"
#include "maille/limits.hpp"

namespace maille {

namespace {

// Reads the declared keys in order (builder_keys.cpp) and runs `at` right after the key named
// `key` (the size budget is checked there, against the model).
template <class P, class F>
void read_keys_with(TomlCursor& t, P& p, std::span<const StageKey<P>> keys, std::string_view key,
                    F&& at) {
  for (const auto& k : keys) {
    if (k.read && !k.first) read_declared(t, p, k);
    if (k.key == key) at();
  }
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
  read_keys_with(t, p, flag_keys(), "resolution", [&] {
    const std::uint64_t n = times(p.nx, p.ny);
    budget(t, "resolution", m, n, times(n, 6), times(n, 2));  // structural, shear, bending
  });
  return guarded(t, [&] { return build_flag(m, p, name); });
}

Group rope(TomlCursor& t, Model& m, const std::string& name) {
  RopeParams p;
  read_keys_with(t, p, rope_keys(), "points",
                 [&] { budget(t, "points", m, p.points, 2 * std::uint64_t(p.points), 0); });
  return guarded(t, [&] { return build_rope(m, p, name); });
}

Group net(TomlCursor& t, Model& m, const std::string& name) {
  NetParams p;
  read_keys_with(t, p, net_keys(), "resolution", [&] {
    const std::uint64_t n = times(p.nx, p.ny);
    budget(t, "resolution", m, n, times(n, 2), 0);
  });
  return guarded(t, [&] { return build_net(m, p, name); });
}

Group membrane(TomlCursor& t, Model& m, const std::string& name) {
  MembraneParams p;
  read_keys_with(t, p, membrane_keys(), "rings", [&] {
    // Lattice points in the disk: about (2 pi / sqrt 3) rings^2; 3 links and 2 faces each.
    const std::uint64_t r = std::uint64_t(p.rings) + 2;
    const std::uint64_t n = times(times(r, r), 4);
    budget(t, "rings", m, n, times(n, 3), times(n, 2));
  });
  return guarded(t, [&] { return build_membrane(m, p, name); });
}

Group lattice(TomlCursor& t, Model& m, const std::string& name) {
  LatticeParams p;
  read_keys_with(t, p, lattice_keys(), "resolution", [&] {
    // 3 structural, 6 face-diagonal and 4 body-diagonal links per point; outer faces.
    const auto& r = p.resolution;
    const std::uint64_t n = times(times(r[0], r[1]), r[2]);
    budget(t, "resolution", m, n, times(n, 13), times(n, 2));
  });
  return guarded(t, [&] { return build_lattice(m, p, name); });
}

Group floor(TomlCursor& t, Model& m, const std::string& name) {
  FloorParams p;
  read_keys_with(t, p, floor_keys(), "resolution",
                 [&] { budget(t, "resolution", m, times(p.nx, p.nz), 0, 0); });
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
