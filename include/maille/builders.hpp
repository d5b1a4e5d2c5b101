// Builders: parameterised models made of bricks (flag, rope, net, membrane, lattice, floor).
// Each appends points, links (spring_damper) and faces to a model and records a named group.
// Scene files reach them through [[flag]], [[rope]], ... tables (docs/scene-format.md).
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "maille/model.hpp"
#include "maille/names.hpp"

namespace maille {

// Which points a builder fixes (`fixed = "..."` in scene files), one choice per builder.
enum class FlagFixed : std::uint8_t { pole, corners, top, top_corners, ends, none };
enum class RopeFixed : std::uint8_t { start, end, both, none };
enum class NetFixed : std::uint8_t { corners, ends, edges, top, all, none };
enum class LatticeFixed : std::uint8_t { none, bottom };
enum class LatticeShape : std::uint8_t { box, ball };

template <>
struct NameTable<FlagFixed> {
  static constexpr std::string_view what = "flag fixed mode";
  static constexpr std::array<Name<FlagFixed>, 6> names{{
      {FlagFixed::pole, "pole", "the column i = 0"},
      {FlagFixed::corners, "corners", "the two pole corners"},
      {FlagFixed::top, "top", "the row j = ny - 1"},
      {FlagFixed::top_corners, "top_corners", "the two top corners"},
      {FlagFixed::ends, "ends", "the columns i = 0 and i = nx - 1"},
      {FlagFixed::none, "none", "nothing fixed"},
  }};
};
template <>
struct NameTable<RopeFixed> {
  static constexpr std::string_view what = "rope fixed mode";
  static constexpr std::array<Name<RopeFixed>, 4> names{{
      {RopeFixed::start, "start", "the first point"},
      {RopeFixed::end, "end", "the last point"},
      {RopeFixed::both, "both", "both ends"},
      {RopeFixed::none, "none", "nothing fixed"},
  }};
};
template <>
struct NameTable<NetFixed> {
  static constexpr std::string_view what = "net fixed mode";
  static constexpr std::array<Name<NetFixed>, 6> names{{
      {NetFixed::corners, "corners", "the four corners"},
      {NetFixed::ends, "ends", "the first and last columns"},
      {NetFixed::edges, "edges", "the whole border"},
      {NetFixed::top, "top", "the last row"},
      {NetFixed::all, "all", "every point"},
      {NetFixed::none, "none", "nothing fixed"},
  }};
};
template <>
struct NameTable<LatticeFixed> {
  static constexpr std::string_view what = "lattice fixed mode";
  static constexpr std::array<Name<LatticeFixed>, 2> names{{
      {LatticeFixed::none, "none", "nothing fixed"},
      {LatticeFixed::bottom, "bottom", "the lowest layer along y"},
  }};
};
template <>
struct NameTable<LatticeShape> {
  static constexpr std::string_view what = "lattice shape";
  static constexpr std::array<Name<LatticeShape>, 2> names{{
      {LatticeShape::box, "box", "every point of the box"},
      {LatticeShape::ball, "ball", "the ball inscribed in the box"},
  }};
};

// Shared by the grid builders: material of the links.
struct LinkMaterial {
  Real stiffness = 100;  // N/m, structural links
  Real damping = 0;      // N.s/m, every link
};

// Cloth on a rectangular grid: structural, shear (diagonals) and bending (every other point)
// spring-dampers, two faces per cell. Point (i, j) has index first + j * nx + i; i runs along
// `along` (the width), j along `up` (the height); (0, 0) is at `origin`.
struct FlagParams {
  Vec3 origin{};                   // m, bottom corner on the pole
  Vec3 along{1, 0, 0};             // unit direction of the width (away from the pole)
  Vec3 up{0, 1, 0};                // unit direction of the height (along the pole)
  Real width = Real(1.5);          // m
  Real height = 1;                 // m
  std::uint32_t nx = 30, ny = 20;  // points along width and height, >= 2
  Real mass = Real(0.3);           // kg, total
  LinkMaterial material{200, Real(0.05)};
  Real shear_stiffness = 100;         // N/m
  Real bending_stiffness = 20;        // N/m (0: no bending links)
  FlagFixed fixed = FlagFixed::pole;  // which points are fixed
};
Group build_flag(Model& m, const FlagParams& p, const std::string& name);

// A chain of points from `start` to `end` with spring-dampers between neighbours (and between
// every other point when bending_stiffness > 0).
struct RopeParams {
  Vec3 start{};
  Vec3 end{1, 0, 0};
  std::uint32_t points = 20;  // >= 2
  Real mass = 1;              // kg, total
  LinkMaterial material{1000, Real(0.1)};
  Real bending_stiffness = 0;  // N/m
  RopeFixed fixed = RopeFixed::start;
  Real pretension = 0;  // relative: rest lengths are (1 - pretension) times the built distance
                        // (a string fixed at both ends is then under tension k pretension L)
};
Group build_rope(Model& m, const RopeParams& p, const std::string& name);

// A net: a grid of points joined only by structural cords (no faces, no shear).
struct NetParams {
  Vec3 origin{};
  Vec3 along{1, 0, 0};
  Vec3 across{0, 0, 1};
  Real width = 1, depth = 1;  // m
  std::uint32_t nx = 15, ny = 15;
  Real mass = 1;  // kg, total
  LinkMaterial material{500, Real(0.05)};
  NetFixed fixed = NetFixed::corners;
  Real pretension = 0;  // rest lengths (1 - pretension) x built: a square drum skin, fixed edges
};
Group build_net(Model& m, const NetParams& p, const std::string& name);

// A drum skin: a disk of points on a triangular lattice, every lattice neighbour joined, the
// whole boundary ring fixed (a closed boundary).
struct MembraneParams {
  Vec3 center{};
  Vec3 normal{0, 1, 0};
  Real radius = Real(0.5);   // m
  std::uint32_t rings = 10;  // lattice points along a radius, >= 2
  Real mass = Real(0.2);     // kg, total over free points
  LinkMaterial material{300, Real(0.02)};
  Real pretension = 0;  // relative: rest lengths are (1 - pretension) times the built distance
};
Group build_membrane(Model& m, const MembraneParams& p, const std::string& name);

// A 3-D lattice of points in a box (or the ball inscribed in it): structural links along the
// axes, shear links across faces and through cubes. Its outer faces form the surface.
struct LatticeParams {
  Vec3 origin{};                                     // m, minimum corner
  Vec3 size{1, 1, 1};                                // m
  std::array<std::uint32_t, 3> resolution{5, 5, 5};  // points per axis, >= 2
  LatticeShape shape = LatticeShape::box;
  Real mass = 1;  // kg, total
  LinkMaterial material{2000, Real(0.5)};
  Real shear_stiffness = 1000;  // N/m, face and body diagonals
  Vec3 velocity{};              // m/s, initial velocity of every point
  LatticeFixed fixed = LatticeFixed::none;
};
Group build_lattice(Model& m, const LatticeParams& p, const std::string& name);

// A floor: a horizontal grid of fixed points (normal +y), for conditional contacts.
struct FloorParams {
  Vec3 center{};
  Real width = 2, depth = 2;  // m, along x and z
  std::uint32_t nx = 20, nz = 20;
};
Group build_floor(Model& m, const FloorParams& p, const std::string& name);

// Conditional links between every pair (one point from each group, at least one free).
struct ContactParams {
  Real stiffness = 1000;       // N/m
  Real damping = 0;            // N.s/m
  Real threshold = Real(0.1);  // m
  Real rest_length = -1;       // m; < 0: the threshold
};
std::size_t build_contacts(Model& m, const Group& a, const Group& b, const ContactParams& p);

}  // namespace maille

namespace maille {

// A square cloth (a `flag` with nothing fixed) folded like an accordion: layers of `fold`
// columns, `gap` spacings apart, with a wave of `wave` spacings across. Layers lie within a
// spacing of each other far from their topological neighbours: the crumpled cloth of the
// self-collision tests, benchmarks and study (one scenario, many uses).
struct CrumpledClothParams {
  std::uint32_t n = 64;    // points per side, >= 2
  Real size = 1;           // m, side of the flat cloth
  std::uint32_t fold = 4;  // columns per layer, >= 1
  Real gap = Real(0.6);    // distance between layers, in spacings
  Real wave = Real(0.3);   // amplitude of the wave across, in spacings
};
Group build_crumpled_cloth(Model& m, const CrumpledClothParams& p, const std::string& name);

}  // namespace maille
