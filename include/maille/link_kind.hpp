// What a link kind (a Link brick) is: the concept a kind satisfies and the records around it.
// The typed pool that stores one kind is in link_pool.hpp, the model's set of pools in
// link_set.hpp; how a pool is run on CPU threads is private (detail/cpu_schedule.hpp).
//
// Checklist for a new kind (see docs/architecture.md, "Adding a link kind"):
//   1. a struct with `keyword`, a plain `Params` record, `fields` (scene keys with unit and bound),
//      and pure functions `force`, `energy`, `stiffness`, `damping` (optionally `is_active`);
//      Params may hold more members than `fields` lists (per-link data set by code: an index, a
//      shape), as long as it stays a plain record;
//   2. one line `registry.add<YourKind>()` (built-ins: src/links/builtin_kinds.cpp);
//   3. optionally, to run on the GPU backend too: write `force` as a function of
//      include/maille/detail/link_laws.glsl (shared by C++ and GLSL, signature (xa, xb, va, vb,
//      fields in order), at most 4 fields) and name it in `static constexpr std::string_view
//      shared_law`; kinds without one make the GPU backend refuse the scene, naming the kind.
// The simulator loop never changes: it folds over the model's pools, one virtual call per pool,
// and each pool runs a tight, inlined loop over its own records.
#pragma once

#include <array>
#include <concepts>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>

#include "maille/mat3.hpp"
#include "maille/vec3.hpp"

namespace maille {

struct LinkEnds {
  std::uint32_t a = 0, b = 0;  // point indices; the force returned by a kind acts on a, -f on b
};

enum class Bound : std::uint8_t { positive, non_negative, any };

// One scene-settable parameter of a link kind.
template <class Params>
struct ParamField {
  std::string_view name;  // scene key
  std::string_view unit;  // SI unit, for docs and messages
  Real Params::*member;
  Bound bound = Bound::positive;
  std::optional<Real> default_value{};  // none: required (unless default_is_distance)
  bool default_is_distance = false;     // omitted: the distance between the points when built
  std::string_view doc{};
  std::string_view default_from{};  // omitted: the value of this other field
};

// The type-erased view of a field, as the scene reader and `maille info` see it.
struct ParamInfo {
  std::string name, unit, doc;
  Bound bound = Bound::positive;
  std::optional<Real> default_value;
  bool default_is_distance = false;
  std::string default_from;
};

template <class K>
concept LinkKind = requires(const Vec3& x, const typename K::Params& p) {
  { K::keyword } -> std::convertible_to<std::string_view>;
  { K::fields.size() } -> std::convertible_to<std::size_t>;
  { K::force(x, x, x, x, p) } -> std::same_as<Vec3>;    // force on a (b receives -force)
  { K::energy(x, x, p) } -> std::convertible_to<Real>;  // potential energy, J
  { K::stiffness(p) } -> std::convertible_to<Real>;     // bound on |df/dx|, N/m (stability)
  { K::damping(p) } -> std::convertible_to<Real>;       // bound on |df/dv|, N.s/m (stability)
};

// Running totals a pool reports after a force pass.
struct LinkCounters {
  std::uint64_t active = 0;  // links that produced a force (conditional kinds)
};

// The link that looks worst after a blow-up: non-finite, or most stretched relative to rest.
struct WorstLink {
  std::size_t index = 0;
  LinkEnds ends{};
  Real badness = 0;  // |d - d0| / d0, or +inf when positions or force are not finite
};

}  // namespace maille
