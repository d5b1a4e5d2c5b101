// The keys a canonical shape gives a scene table ([[obstacle]], [[geometric_point]]), declared
// from the shape table (shapes.hpp) rather than per shape: `shape`, the choice of a row, and one
// number key per shape parameter (a cone's `top`, a torus's `tube`), which only its shape takes
// ("only a torus has a tube" on another). A table's settings say where they hold the shape with
// an `Access` type:
//
//   struct ObstacleShape {
//     static auto& kind(auto& o) { return o.shape; }                // ShapeKind
//     static auto& parameter(auto& o) { return o.shape_parameter; } // std::optional<Real>
//     static bool canonical(const Obstacle& o) { return !o.mesh; }  // false: no shape's keys
//   };
//
// A parameter key reads and checks like stage_keys.hpp's number(): the bound, then lo <= value
// <= hi ("must be in [0, 1] (got 1.5)"); its value, as `maille info` and checkpoints see it, is
// the settings' parameter when the shape is its own, else the parameter's default.
#pragma once

#include <cstddef>
#include <optional>
#include <span>
#include <string>
#include <utility>
#include <vector>

#include "maille/shapes.hpp"
#include "maille/stage_keys.hpp"

namespace maille {

namespace shape_key_detail {

// The shapes with a parameter, in the order of their keys: the table's last row first (the
// order, `tube` then `top`, of the keys written before the shape table: a checkpoint's
// fingerprint hashes them in order).
std::span<const ShapeKind> parameter_shapes();

template <class S, class A>
void read(SceneTable& t, S& s, const StageKey<S>& k) {
  const Real r = t.real(k.key, shape_parameter(A::kind(s), A::parameter(s)), k.bound);
  if (k.hi > k.lo) t.check_range(k.key, r, k.lo, k.hi, k.info.unit);
  A::parameter(s) = r;
}

// Slot I: the I-th shape of parameter_shapes() (StageKey's functions take no state).
template <class S, class A, std::size_t I>
bool applies(const S& s) {
  return A::canonical(s) && A::kind(s) == parameter_shapes()[I];
}
template <class S, class A, std::size_t I>
std::string value(const S& s) {
  const ShapeKind own = parameter_shapes()[I];
  const std::optional<Real> p = A::kind(s) == own ? A::parameter(s) : std::nullopt;
  return key_detail::number_text(double(shape_parameter(own, p)));
}
template <class S, class A, std::size_t I>
StageKey<S> slot() {
  const ShapeParameter& p = *shape_row(parameter_shapes()[I]).parameter;
  StageKey<S> k{
      p.key,      KeyType::number, {.doc = p.doc, .range_doc = p.range_doc}, p.bound, p.lo, p.hi,
      read<S, A>, value<S, A, I>};
  k.applies = applies<S, A, I>;
  k.refusal = p.refusal;
  return k;
}

}  // namespace shape_key_detail

// The `shape` key: one of the table's names.
template <class S, class A>
StageKey<S> shape_key(KeyDoc d) {
  return {"shape",
          KeyType::choice,
          d,
          Bound::any,
          0,
          0,
          [](SceneTable& t, S& s, const StageKey<S>& k) {
            const std::string name =
                t.text(k.key, std::string(to_string(A::kind(s))), shape_names());
            A::kind(s) = shape_kind(name);
          },
          [](const S& s) { return std::string(to_string(A::kind(s))); },
          [] { return shape_name_list(); }};
}

// The parameters' keys, one per shape that has a parameter.
template <class S, class A>
std::vector<StageKey<S>> shape_parameter_keys() {
  const std::size_t count = shape_key_detail::parameter_shapes().size();
  std::vector<StageKey<S>> keys;
  [&]<std::size_t... I>(std::index_sequence<I...>) {
    ((I < count ? keys.push_back(shape_key_detail::slot<S, A, I>()) : void()), ...);
  }
  (std::make_index_sequence<kMaxShapeParameters>{});
  return keys;
}

// "canonical shapes of unit size: `sphere`: radius 1; ...": every row's name and doc, for a
// `shape` key's doc.
std::string_view shape_docs();

}  // namespace maille
