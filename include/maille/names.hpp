// Names of enumerated choices, declared once. An enum whose values scene files, the command line
// or tools spell as words specialises NameTable next to its declaration:
//
//   template <> struct NameTable<BroadPhase> {
//     static constexpr std::string_view what = "broad phase";
//     static constexpr std::array<Name<BroadPhase>, 4> names{{
//         {BroadPhase::brute, "brute", "every pair tested (the reference)"}, ...}};
//   };
//
// and everything else reads that table: parsing (`parse_name`, `SceneTable::choice`),
// `to_string`, the list of choices in error messages (`name_list`), the viewer's options
// (`name_strings`) and the documentation (unit.Names.* checks docs/scene-format.md against it).
// A name added to the table is known everywhere at once; there is no string-to-enum chain to
// forget (one used to turn a new name silently into its last branch).
#pragma once

#include <array>
#include <cstddef>
#include <optional>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

namespace maille {

template <class E>
struct Name {
  E value;
  std::string_view name;  // as written in scene files and on the command line
  std::string_view doc;   // one line, for docs and help
};

template <class E>
struct NameTable;  // specialised per enum, next to the enum

template <class E>
concept Named = requires {
  { NameTable<E>::what } -> std::convertible_to<std::string_view>;
  NameTable<E>::names.size();
};

template <Named E>
constexpr std::string_view to_string(E value) {
  for (const auto& n : NameTable<E>::names)
    if (n.value == value) return n.name;
  return "?";  // a value missing from its table: unit.Names.* catches it
}

template <Named E>
constexpr std::optional<E> parse_name(std::string_view name) {
  for (const auto& n : NameTable<E>::names)
    if (n.name == name) return n.value;
  return std::nullopt;
}

// The value's one-line description.
template <Named E>
constexpr std::string_view doc_of(E value) {
  for (const auto& n : NameTable<E>::names)
    if (n.value == value) return n.doc;
  return "";
}

// The names in table order, as string views (for SceneTable::text's choices).
template <Named E>
constexpr auto name_views() {
  std::array<std::string_view, NameTable<E>::names.size()> out{};
  for (std::size_t i = 0; i < out.size(); ++i) out[i] = NameTable<E>::names[i].name;
  return out;
}

// The names as strings (live options, combos).
template <Named E>
std::vector<std::string> name_strings() {
  std::vector<std::string> out;
  for (const auto& n : NameTable<E>::names) out.emplace_back(n.name);
  return out;
}

// "brute, uniform, hashed, hierarchical": the list error messages show.
template <Named E>
std::string name_list(std::string_view separator = ", ") {
  std::string out;
  for (const auto& n : NameTable<E>::names) {
    if (!out.empty()) out += separator;
    out += n.name;
  }
  return out;
}

// The one rule of every registry (link kinds, stage tables, integrators, backends, the GPU's
// stages): a name is registered once; a second entry under it is a programming error, thrown as
// std::logic_error naming the registry and the name (never a silent replacement, never a second
// entry that lookups skip).
[[noreturn]] inline void registered_twice(std::string_view registry, std::string_view name) {
  throw std::logic_error(std::string(registry) + ": '" + std::string(name) +
                         "' is already registered");
}

}  // namespace maille
