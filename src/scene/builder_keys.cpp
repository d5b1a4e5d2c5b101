// The builders' keys (builder_keys.hpp), in the order builder_tables.cpp reads them. Physical
// bounds (maille/limits.hpp): a stiffness or damping within 1e12, a length within the +-1e6 m
// box, a total mass of at least 1e-12 kg.
#include "builder_keys.hpp"

#include <array>

#include "maille/limits.hpp"

namespace maille {

namespace {

constexpr std::int64_t kMaxRes = 1 << 14;  // points along a rope or a membrane's radius
constexpr std::int64_t kMaxAxis = std::int64_t{limits::max_points};  // points along an axis

template <auto M, auto... More>
constexpr auto length(std::string_view key, KeyDoc d) {
  d.unit = "m";
  return number<M, More...>(key, Bound::positive, 0, 2 * limits::max_coordinate, d);
}

template <auto M, auto... More>
constexpr auto mass(KeyDoc d) {
  d.unit = "kg";
  d.range_doc = "[1e-12, 1e12]";
  return number<M, More...>("mass", Bound::positive, limits::min_mass, limits::max_mass, d);
}

// A stiffness (N/m) or, for a key naming damping, a damping (N.s/m).
template <auto M, auto... More>
constexpr auto stiffness(std::string_view key, KeyDoc d) {
  d.unit = key.find("damping") != std::string_view::npos ? "N.s/m" : "N/m";
  return number<M, More...>(key, Bound::non_negative, 0, limits::max_stiffness, d);
}

// The structural stiffness and the damping of every link: LinkMaterial.
template <class P>
constexpr std::array<StageKey<P>, 2> material(std::string_view stiffness_doc,
                                              std::string_view damping_doc) {
  return {stiffness<&P::material, &LinkMaterial::stiffness>("stiffness", {.doc = stiffness_doc}),
          stiffness<&P::material, &LinkMaterial::damping>("damping", {.doc = damping_doc})};
}

template <auto M>
constexpr auto pretension(std::string_view doc) {
  using P = key_detail::owner_t<M>;
  return checked(
      number<M>("pretension", Bound::non_negative, 0, 0, {.doc = doc, .range_doc = "[0, 1)"}),
      [](SceneTable& t, const P& p) {
        if (p.*M >= 1) t.fail("pretension", "must be < 1");
      });
}

// A resolution: an array of integers >= 2, one per axis, read into `Axes` in order
// (builder_tables.cpp then checks the size budget against the model right after it).
template <auto X, auto... Rest>
constexpr auto resolution(std::string_view type, std::string_view default_doc) {
  using P = key_detail::owner_t<X>;
  return parsed<P>("resolution", KeyType::custom,
                   {.unit = "points",
                    .doc = "points along each axis",
                    .default_doc = default_doc,
                    .range_doc = ">= 2 each",
                    .type_doc = type},
                   [](SceneTable& t, P& p, const StageKey<P>& k) {
                     const auto res = t.integers(
                         k.key, {std::int64_t(p.*X), std::int64_t(p.*Rest)...}, 2, kMaxAxis);
                     p.*X = static_cast<std::uint32_t>(res[0]);
                     std::size_t i = 1;
                     ((p.*Rest = static_cast<std::uint32_t>(res[i++])), ...);
                   });
}

template <class S, std::size_t N, std::size_t K>
constexpr std::array<StageKey<S>, N + K> join(const std::array<StageKey<S>, N>& a,
                                              const std::array<StageKey<S>, K>& b) {
  std::array<StageKey<S>, N + K> out{};
  for (std::size_t i = 0; i < N; ++i) out[i] = a[i];
  for (std::size_t i = 0; i < K; ++i) out[N + i] = b[i];
  return out;
}

}  // namespace

std::span<const StageKey<FlagParams>> flag_keys() {
  using P = FlagParams;
  static const auto keys = join(
      join(
          std::array<StageKey<P>, 7>{
              vector<&P::origin>("origin",
                                 {.unit = "m", .doc = "corner (0, 0), at the bottom of the pole"}),
              vector<&P::along>("along", {.doc = "direction of the width (away from the pole)"}),
              vector<&P::up>("up", {.doc = "direction of the height (along the pole)"}),
              length<&P::width>("width", {}),
              length<&P::height>("height", {}),
              resolution<&P::nx, &P::ny>("[nx, ny]", "`[30, 20]`"),
              mass<&P::mass>({.doc = "total, shared equally"}),
          },
          material<P>("structural links", "every link")),
      std::array<StageKey<P>, 3>{
          number_from<&P::shear_stiffness>(
              "shear_stiffness", Bound::non_negative, 0, limits::max_stiffness,
              [](const P& p) { return p.material.stiffness / 2; },
              {.unit = "N/m", .doc = "diagonal links", .default_doc = "`stiffness / 2`"}),
          number_from<&P::bending_stiffness>(
              "bending_stiffness", Bound::non_negative, 0, limits::max_stiffness,
              [](const P& p) { return p.material.stiffness / 10; },
              {.unit = "N/m", .doc = "every-other-point links", .default_doc = "`stiffness / 10`"}),
          choice<&P::fixed>("fixed", {.doc = "`pole`: the column i = 0; `corners`: its two ends; "
                                             "`top`: the row j = ny−1; `ends`: the columns i = 0 "
                                             "and i = nx−1"}),
      });
  return keys;
}

std::span<const StageKey<RopeParams>> rope_keys() {
  using P = RopeParams;
  static const auto keys =
      join(join(
               std::array<StageKey<P>, 4>{
                   vector<&P::start>("start", {.unit = "m", .doc = "the first point"}),
                   vector<&P::end>("end", {.unit = "m", .doc = "the last point (a straight rope)"}),
                   integer<&P::points>("points", 2, kMaxRes, {.doc = "points along the rope"}),
                   mass<&P::mass>({.doc = "total"}),
               },
               material<P>("neighbour links", "every link")),
           std::array<StageKey<P>, 3>{
               stiffness<&P::bending_stiffness>(
                   "bending_stiffness", {.doc = "every-other-point links (0: a free chain)"}),
               choice<&P::fixed>("fixed", {.doc = "the fixed ends"}),
               pretension<&P::pretension>(
                   "rest lengths are (1 − pretension) × built length: between fixed ends, a string "
                   "under tension stiffness × pretension × spacing"),
           });
  return keys;
}

std::span<const StageKey<NetParams>> net_keys() {
  using P = NetParams;
  static const auto keys =
      join(join(
               std::array<StageKey<P>, 7>{
                   vector<&P::origin>("origin", {.unit = "m", .doc = "corner (0, 0)"}),
                   vector<&P::along>("along", {.doc = "grid direction of the width"}),
                   vector<&P::across>("across", {.doc = "grid direction of the depth"}),
                   length<&P::width>("width", {}),
                   length<&P::depth>("depth", {}),
                   resolution<&P::nx, &P::ny>("[nx, ny]", "`[15, 15]`"),
                   mass<&P::mass>({.doc = "total"}),
               },
               material<P>("every link", "every link")),
           std::array<StageKey<P>, 2>{
               choice<&P::fixed>("fixed", {.doc = "`ends`: first and last columns"}),
               pretension<&P::pretension>(
                   "rest lengths are (1 − pretension) × built length: with `fixed = \"edges\"`, a "
                   "square drum skin under tension stiffness × pretension per unit length "
                   "(bench/scenes/play_square_drum.toml)"),
           });
  return keys;
}

std::span<const StageKey<MembraneParams>> membrane_keys() {
  using P = MembraneParams;
  static const auto keys = join(
      join(
          std::array<StageKey<P>, 5>{
              vector<&P::center>("center", {.unit = "m", .doc = "the disk's centre"}),
              vector<&P::normal>("normal", {.doc = "the disk's normal"}),
              length<&P::radius>("radius", {}),
              integer<&P::rings>("rings", 2, kMaxRes, {.doc = "lattice points along a radius"}),
              mass<&P::mass>({.doc = "total over the free points"}),
          },
          material<P>("every link", "every link")),
      std::array<StageKey<P>, 1>{
          pretension<&P::pretension>("rest lengths are (1 − pretension) × built length"),
      });
  return keys;
}

std::span<const StageKey<LatticeParams>> lattice_keys() {
  using P = LatticeParams;
  static const auto keys = join(
      join(
          std::array<StageKey<P>, 5>{
              vector<&P::origin>("origin", {.unit = "m", .doc = "minimum corner"}),
              checked(vector<&P::size>(
                          "size",
                          {.unit = "m", .doc = "extent along x, y and z", .range_doc = "> 0 each"}),
                      [](SceneTable& t, const P& p) {
                        if (!(p.size.x > 0 && p.size.y > 0 && p.size.z > 0))
                          t.fail("size", "must be > 0 on every axis");
                      }),
              parsed<P>("resolution", KeyType::custom,
                        {.unit = "points",
                         .doc = "points along each axis",
                         .default_doc = "`[5, 5, 5]`",
                         .range_doc = ">= 2 each",
                         .type_doc = "[nx, ny, nz]"},
                        [](SceneTable& t, P& p, const StageKey<P>& k) {
                          auto& r = p.resolution;
                          const auto res = t.integers(k.key, {r[0], r[1], r[2]}, 2, kMaxAxis);
                          for (std::size_t i = 0; i < 3; ++i)
                            r[i] = static_cast<std::uint32_t>(res[i]);
                        }),
              choice<&P::shape>("shape", {.doc = "`ball`: the points inside the inscribed sphere"}),
              mass<&P::mass>({.doc = "total"}),
          },
          material<P>("axis neighbours", "every link")),
      std::array<StageKey<P>, 3>{
          number_from<&P::shear_stiffness>(
              "shear_stiffness", Bound::non_negative, 0, limits::max_stiffness,
              [](const P& p) { return p.material.stiffness / 2; },
              {.unit = "N/m", .doc = "face and body diagonals", .default_doc = "`stiffness / 2`"}),
          vector<&P::velocity>("velocity",
                               {.unit = "m/s", .doc = "initial velocity of every point"}),
          choice<&P::fixed>("fixed", {.doc = "`bottom`: the lowest layer along y"}),
      });
  return keys;
}

std::span<const StageKey<FloorParams>> floor_keys() {
  using P = FloorParams;
  static const std::array<StageKey<P>, 4> keys{
      vector<&P::center>("center", {.unit = "m", .doc = "the grid's centre"}),
      length<&P::width>("width", {.doc = "along x"}),
      length<&P::depth>("depth", {.doc = "along z"}),
      resolution<&P::nx, &P::nz>("[nx, nz]", "`[20, 20]`"),
  };
  return keys;
}

}  // namespace maille
