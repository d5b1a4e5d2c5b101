// Keys of a stage table ([self_collision], [[obstacle]], [fields.wind], ...), declared once, the
// way link kinds declare their `fields`: key, type, unit, bound and range, default (the settings
// struct's member initialiser), which methods use it, one line of doc. From the declarations
// come
//   - parsing: read_keys() reads every declared key into the settings, with the table getters'
//     checks and messages (bound first, then "must be in [lo, hi] UNIT (got v)");
//   - the "not used by method" gate: a key that the chosen method does not use is an error
//     naming the key and the method (check_methods());
//   - the documentation: describe_keys() gives one KeyInfo per key, markdown_rows() the rows of
//     docs/scene-format.md's tables (unit.StageKeys.* fails when the two disagree), and
//     `maille info --keys` prints them;
//   - the resolved values: visit_keys() calls a function with every declared key and its value
//     as text (`maille info` shows them; checkpoints' model fingerprints can hash them).
// A key whose value is not one of the plain types carries its own reader in its declaration
// (`parsed`: a mesh file, a MIDI source, a [low, high] pair), so that every key is read the same
// way. Keys that resolve against the model (point references, groups paired with their sources
// in the file) or into a value no member holds alone (an obstacle's placement) are declared too,
// with `custom`: the table's parser reads them, the declaration documents them and takes part in
// the gate.
#pragma once

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cstdint>
#include <span>
#include <stdexcept>
#include <string>
#include <string_view>
#include <type_traits>
#include <utility>
#include <vector>

#include "maille/names.hpp"
#include "maille/scene_table.hpp"
#include "maille/vec3.hpp"

namespace maille {

enum class KeyType : std::uint8_t {
  number,
  integer,
  choice,
  vector,
  text,
  texts,
  table,
  number_or_auto,
  custom
};

// The documentation half of a declaration (designated initialisers: {.unit = "m", .doc = ...}).
struct KeyDoc {
  std::string_view unit{};
  std::string_view methods{};      // names of the methods using the key, ", "-separated; empty: all
  std::string_view doc{};          // one line
  std::string_view default_doc{};  // when the default is not the member's initial value
  std::string_view range_doc{};    // when the range is not the declared bound and [lo, hi]
  std::string_view type_doc{};     // the type as the docs say it, when not the KeyType's
  bool required = false;           // number keys: no default, the table must give it
};

template <class S>
struct StageKey {
  std::string_view key;
  KeyType type = KeyType::custom;
  KeyDoc info{};
  Bound bound = Bound::any;  // number keys
  Real lo = 0, hi = 0;       // number and integer keys: the range checked after the bound
  // Reads the key into the settings (null for custom keys: the table's parser reads them).
  void (*read)(SceneTable&, S&, const StageKey&) = nullptr;
  // The value in the settings as text (null: a key whose value is not kept as such).
  std::string (*value)(const S&) = nullptr;
  std::string (*choices)() = nullptr;  // choice keys: "a, b, c"
  // Number keys whose default is another key's value (read before it), like the link kinds'
  // `default_from`: [[contact]]'s rest_length defaults to its threshold.
  Real (*default_from)(const S&) = nullptr;
  // A check beyond the type, bound and range, run right after the key is read ("must be < 1"):
  // its message names the key like every other.
  void (*check)(SceneTable&, const S&) = nullptr;
  // Read by the parser itself, with read_key, before the others (read_keys skips it): a key
  // that decides what the rest means (an obstacle's method), or that the parser checks against
  // the model before the others are read (groups).
  bool first = false;
  // A key that only some settings take (a torus's tube, a MIDI source's channel): when
  // `applies` says no, the key is not read and its presence is refused with `refusal`.
  bool (*applies)(const S&) = nullptr;
  std::string_view refusal{};
};

// The type-erased view of a declaration, as the docs and `maille info --keys` show it.
struct KeyInfo {
  std::string key, type, unit, default_value, range, methods, doc;
  std::string group{};  // tables with a first column (the link kinds' "kind"): its cell
};

namespace key_detail {

template <class M>
struct member;
template <class C, class T>
struct member<T C::*> {
  using owner = C;
  using type = T;
};
template <auto M>
using owner_t = typename member<decltype(M)>::owner;

// The member a chain of member pointers names: at<&Flag::material, &Material::stiffness>(flag)
// is flag.material.stiffness (a key of a nested record, declared on the outer one).
template <auto M, auto... More, class T>
constexpr auto& at(T& s) {
  return ((s.*M).*....*More);  // a left fold over the chain
}
template <auto M, auto... More>
using type_t = std::remove_cvref_t<decltype(at<M, More...>(std::declval<owner_t<M>&>()))>;

// Every `from` in s replaced by `to` (built by appending: GCC 12's -Wrestrict misreads
// std::string::replace at -O3).
inline std::string replace_all(std::string_view s, std::string_view from, std::string_view to) {
  std::string out;
  for (std::size_t at = 0;;) {
    const std::size_t next = s.find(from, at);
    if (next == std::string_view::npos) return out.append(s.substr(at));
    out.append(s.substr(at, next - at)).append(to);
    at = next + from.size();
  }
}

// Shortest text that reads back to the same double ("0.5", "1e-06" -> "1e-6", "2000").
inline std::string number_text(double v) {
  char buf[32];
  const auto end = std::to_chars(buf, buf + sizeof buf, v).ptr;  // shortest round trip
  return replace_all(
      replace_all(replace_all(std::string_view(buf, std::size_t(end - buf)), "e-0", "e-"), "e+0",
                  "e"),
      "e+", "e");
}
inline std::string vector_text(const Vec3& v) {
  std::string out = "[";
  out.append(number_text(double(v.x))).append(", ").append(number_text(double(v.y)));
  return out.append(", ").append(number_text(double(v.z))).append("]");
}

// A declaration with no bound or range (choices, vectors, texts, custom keys): its reader, how
// its value shows, and for a choice its names.
template <class S>
constexpr StageKey<S> unbounded(std::string_view key, KeyType type, const KeyDoc& d,
                                void (*read)(SceneTable&, S&, const StageKey<S>&),
                                std::string (*value)(const S&),
                                std::string (*choices)() = nullptr) {
  return {key, type, d, Bound::any, 0, 0, read, value, choices};
}

}  // namespace key_detail

// A number member: bound (> 0, >= 0 or any), then lo <= value <= hi when hi > lo.
template <auto M, auto... More>
constexpr StageKey<key_detail::owner_t<M>> number(std::string_view key, Bound bound, Real lo,
                                                  Real hi, KeyDoc d) {
  using S = key_detail::owner_t<M>;
  return {
      key,
      KeyType::number,
      d,
      bound,
      lo,
      hi,
      [](SceneTable& t, S& s, const StageKey<S>& k) {
        auto& v = key_detail::at<M, More...>(s);
        const Real fallback = k.default_from ? k.default_from(s) : static_cast<Real>(v);
        const Real r = k.info.required ? t.real(k.key, k.bound) : t.real(k.key, fallback, k.bound);
        v = r;
        if (k.hi > k.lo) t.check_range(k.key, r, k.lo, k.hi, k.info.unit);
      },
      [](const S& s) { return key_detail::number_text(double(key_detail::at<M, More...>(s))); }};
}

// A number member whose default is another key's value, `from(s)`, read before it.
template <auto M, auto... More>
constexpr StageKey<key_detail::owner_t<M>> number_from(std::string_view key, Bound bound, Real lo,
                                                       Real hi,
                                                       Real (*from)(const key_detail::owner_t<M>&),
                                                       KeyDoc d) {
  auto k = number<M, More...>(key, bound, lo, hi, d);
  k.default_from = from;
  return k;
}

// An integer member in [lo, hi].
template <auto M, auto... More>
constexpr StageKey<key_detail::owner_t<M>> integer(std::string_view key, std::int64_t lo,
                                                   std::int64_t hi, KeyDoc d) {
  using S = key_detail::owner_t<M>;
  return {key,
          KeyType::integer,
          d,
          Bound::any,
          Real(lo),
          Real(hi),
          [](SceneTable& t, S& s, const StageKey<S>& k) {
            using T = key_detail::type_t<M, More...>;
            key_detail::at<M, More...>(s) = static_cast<T>(
                t.integer(k.key, key_detail::at<M, More...>(s), static_cast<std::int64_t>(k.lo),
                          static_cast<std::int64_t>(k.hi)));
          },
          [](const S& s) { return std::to_string(key_detail::at<M, More...>(s)); }};
}

// A named choice (names.hpp) member.
template <auto M, auto... More>
constexpr StageKey<key_detail::owner_t<M>> choice(std::string_view key, KeyDoc d) {
  using S = key_detail::owner_t<M>;
  using E = key_detail::type_t<M, More...>;
  return key_detail::unbounded<S>(
      key, KeyType::choice, d,
      [](SceneTable& t, S& s, const StageKey<S>& k) {
        key_detail::at<M, More...>(s) = t.choice(k.key, key_detail::at<M, More...>(s));
      },
      [](const S& s) { return std::string(to_string(key_detail::at<M, More...>(s))); },
      [] { return name_list<E>(); });
}

namespace key_detail {

// The table's getter for a member's type, and its value as text: what vector and string members
// differ by.
inline Vec3 get(SceneTable& t, std::string_view key, const Vec3& v) {
  return t.vec3(key, v);
}
inline std::string get(SceneTable& t, std::string_view key, const std::string& v) {
  return t.text(key, v, std::span<const std::string_view>{});
}
inline std::string shown(const Vec3& v) {
  return vector_text(v);
}
inline std::string shown(const std::string& v) {
  return v;
}

// A member read by its type's getter; a required one (no default) missing fails first, with the
// same message, at the table, as every required key's.
template <KeyType Type, auto M, auto... More>
constexpr StageKey<owner_t<M>> got(std::string_view key, const KeyDoc& d) {
  using S = owner_t<M>;
  return unbounded<S>(
      key, Type, d,
      [](SceneTable& t, S& s, const StageKey<S>& k) {
        if (k.info.required && !t.has(k.key)) t.fail(k.key, "is required but missing");
        auto& v = at<M, More...>(s);
        v = get(t, k.key, v);
      },
      [](const S& s) { return shown(at<M, More...>(s)); });
}

}  // namespace key_detail

// A vector member (any finite components; the table's vec3 getter checks them).
template <auto M, auto... More>
constexpr StageKey<key_detail::owner_t<M>> vector(std::string_view key, KeyDoc d) {
  return key_detail::got<KeyType::vector, M, More...>(key, d);
}

// A string member (any text; `required`: no default). Checks beyond the type go in `check`.
template <auto M, auto... More>
constexpr StageKey<key_detail::owner_t<M>> text(std::string_view key, KeyDoc d) {
  return key_detail::got<KeyType::text, M, More...>(key, d);
}

// A string member that must be one of E's names (names.hpp), kept as the text.
template <Named E, auto M, auto... More>
constexpr StageKey<key_detail::owner_t<M>> named_text(std::string_view key, KeyDoc d) {
  using S = key_detail::owner_t<M>;
  auto declared = text<M, More...>(key, d);
  declared.type = KeyType::choice;
  declared.read = [](SceneTable& t, S& s, const StageKey<S>& k) {
    static constexpr auto names = name_views<E>();
    auto& v = key_detail::at<M, More...>(s);
    v = t.text(k.key, v, names);
  };
  declared.choices = [] { return name_list<E>(); };
  return declared;
}

// An array of strings member (groups); `value` (optional) shows it, else its items joined by ",".
template <auto M, auto... More>
constexpr StageKey<key_detail::owner_t<M>> texts(
    std::string_view key, KeyDoc d, std::string (*value)(const key_detail::owner_t<M>&) = nullptr) {
  using S = key_detail::owner_t<M>;
  return key_detail::unbounded<S>(
      key, KeyType::texts, d,
      [](SceneTable& t, S& s, const StageKey<S>& k) {
        auto& v = key_detail::at<M, More...>(s);
        v = t.texts(k.key, v);
      },
      value ? value : +[](const S& s) {
        std::string out;
        for (const auto& item : key_detail::at<M, More...>(s))
          out.append(out.empty() ? "" : ",").append(item);
        return out;
      });
}

// A number member that may also be the text "auto", kept as 0 (the member's automatic value):
// a number is checked against the bound, then lo <= value <= hi when hi > lo.
template <auto M, auto... More>
constexpr StageKey<key_detail::owner_t<M>> number_or_auto(std::string_view key, Bound bound,
                                                          Real lo, Real hi, KeyDoc d) {
  using S = key_detail::owner_t<M>;
  return {key,
          KeyType::number_or_auto,
          d,
          bound,
          lo,
          hi,
          [](SceneTable& t, S& s, const StageKey<S>& k) {
            using T = key_detail::type_t<M, More...>;
            auto& v = key_detail::at<M, More...>(s);
            if (t.has_text(k.key)) {
              t.text(k.key, "auto", {"auto"});
              v = T(0);
            } else {
              v = static_cast<T>(t.real(k.key, static_cast<Real>(v), k.bound));
            }
            if (k.hi > k.lo) t.check_range(k.key, static_cast<Real>(v), k.lo, k.hi, k.info.unit);
          },
          [](const S& s) {
            const auto v = key_detail::at<M, More...>(s);
            return v > 0 ? key_detail::number_text(double(v)) : std::string("auto");
          }};
}

// A key with a reader of its own (a value that is not one of the types above: a mesh file, a
// MIDI source, a [low, high] pair); `value` (optional) shows what it resolved to.
template <class S>
constexpr StageKey<S> parsed(std::string_view key, KeyType type, KeyDoc d,
                             void (*read)(SceneTable&, S&, const StageKey<S>&),
                             std::string (*value)(const S&) = nullptr) {
  return key_detail::unbounded<S>(key, type, d, read, value);
}

// The declaration read by the parser before the others (read_key; read_keys skips it): a key
// that decides what else is read (a method), or one checked against the model first (groups).
template <class S>
constexpr StageKey<S> read_first(StageKey<S> k) {
  k.first = true;
  return k;
}

// A choice read first (above).
template <auto M, auto... More>
constexpr StageKey<key_detail::owner_t<M>> parsed_choice(std::string_view key, KeyDoc d) {
  return read_first(choice<M, More...>(key, d));
}

// The declaration of a key that only some settings take: when `applies(s)` is false (s as read
// so far), the key is not read and a table that gives it fails with `refusal` ("only a torus
// has a tube").
template <class S>
constexpr StageKey<S> only_if(StageKey<S> k, std::type_identity_t<bool (*)(const S&)> applies,
                              std::string_view refusal) {
  k.applies = applies;
  k.refusal = refusal;
  return k;
}

// A key the stage's parser reads itself; `value` (optional) shows what it resolved to.
template <class S>
constexpr StageKey<S> custom(std::string_view key, KeyType type, KeyDoc d,
                             std::string (*value)(const S&) = nullptr) {
  return key_detail::unbounded<S>(key, type, d, nullptr, value);
}

// A key naming a point of the model ("name", "group:index" or a global index: a string or an
// integer), which the table's parser resolves.
template <class S>
constexpr StageKey<S> point_reference(std::string_view key, KeyDoc d) {
  d.type_doc = "string or integer";
  return custom<S>(key, KeyType::custom, d);
}

// The declaration with a check run right after the key is read.
template <class S>
constexpr StageKey<S> checked(StageKey<S> k,
                              std::type_identity_t<void (*)(SceneTable&, const S&)> check) {
  k.check = check;
  return k;
}

// `name`, read first: the element's part of its stage's name and stats.csv columns
// ("obstacle:NAME"), so letters, digits, '_' and '-' only (its parser checks it is unique).
template <auto M, auto... More>
constexpr StageKey<key_detail::owner_t<M>> stage_name(KeyDoc d) {
  using S = key_detail::owner_t<M>;
  d.range_doc = "letters, digits, `_`, `-`; unique";
  return read_first(checked(text<M, More...>("name", d), [](SceneTable& t, const S& s) {
    const std::string& name = key_detail::at<M, More...>(s);
    const bool safe = !name.empty() && std::all_of(name.begin(), name.end(), [](char c) {
      return std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == '-';
    });
    if (!safe) t.fail("name", "use letters, digits, '_' and '-' (it names stats.csv columns)");
  }));
}

// The groups whose points a stage acts on, read first (its parser checks them against the
// model); none: every group.
template <auto M, auto... More>
constexpr StageKey<key_detail::owner_t<M>> acted_groups(std::string_view key, KeyDoc d) {
  using S = key_detail::owner_t<M>;
  d.default_doc = "every group";
  d.range_doc = "existing groups with free points";
  return read_first(texts<M, More...>(key, d, [](const S& s) {
    std::string out;
    for (const auto& g : key_detail::at<M, More...>(s))
      out.append(out.empty() ? "" : ",").append(g);
    return out.empty() ? std::string("every group") : out;
  }));
}

// Reads one declaration that has a reader: its `applies` gate, the reader, its check.
template <class S>
void read_declared(SceneTable& t, S& s, const StageKey<S>& k) {
  if (k.applies && !k.applies(s)) {
    if (t.has(k.key)) t.fail(k.key, std::string(k.refusal));
    return;
  }
  k.read(t, s, k);
  if (k.check) k.check(t, s);
}

// Reads one declared key (parsers whose reading is structural read key by key, in their order).
template <class S>
void read_key(SceneTable& t, S& s, std::span<const StageKey<S>> keys, std::string_view key) {
  for (const auto& k : keys)
    if (k.key == key) {
      if (!k.read) throw std::logic_error("read_key: '" + std::string(key) + "' is custom");
      read_declared(t, s, k);
      return;
    }
  throw std::logic_error("read_key: '" + std::string(key) + "' is not declared");
}

// Whether `method` is among the key's methods (every method when the key names none).
template <class S>
bool used_by(const StageKey<S>& k, std::string_view method) {
  if (k.info.methods.empty() || method.empty()) return true;
  std::string_view rest = k.info.methods;
  while (!rest.empty()) {
    const auto comma = rest.find(',');
    std::string_view word = rest.substr(0, comma);
    while (!word.empty() && word.front() == ' ') word.remove_prefix(1);
    if (word == method) return true;
    rest = comma == std::string_view::npos ? std::string_view{} : rest.substr(comma + 1);
  }
  return false;
}

// "geometric and conditional" from "geometric, conditional".
inline std::string methods_in_words(std::string_view methods) {
  const auto last = methods.rfind(", ");
  if (last == std::string_view::npos) return std::string(methods);
  return std::string(methods.substr(0, last)).append(" and ").append(methods.substr(last + 2));
}

// Fails at the first key present in the table that `method` does not use.
template <class S>
void check_methods(SceneTable& t, std::span<const StageKey<S>> keys, std::string_view method) {
  for (const auto& k : keys)
    if (t.has(k.key) && !used_by(k, method))
      t.fail(k.key, std::string("is not used by method = \"")
                        .append(method)
                        .append("\" (it is a key of ")
                        .append(methods_in_words(k.info.methods))
                        .append(")"));
}

// Reads every declared key that has a reader, but those read first (after the gate, when a
// method is given).
template <class S>
void read_keys(SceneTable& t, S& s, std::span<const StageKey<S>> keys,
               std::string_view method = {}) {
  if (!method.empty()) check_methods(t, keys, method);
  for (const auto& k : keys)
    if (k.read && !k.first) read_declared(t, s, k);
}

// A member read as a sub-table (`[simulation.implicit]`, `[fields.wind]`) by its own declared
// keys, `Keys()`: absent, the member keeps its defaults; present, its keys are read and any
// other is refused (finish).
template <auto Keys, auto M, auto... More>
constexpr StageKey<key_detail::owner_t<M>> subtable(std::string_view key, KeyDoc d) {
  using S = key_detail::owner_t<M>;
  return key_detail::unbounded<S>(
      key, KeyType::table, d,
      [](SceneTable& t, S& s, const StageKey<S>& k) {
        if (auto c = t.child(k.key)) {
          read_keys(*c, key_detail::at<M, More...>(s), Keys());
          c->finish();
        }
      },
      nullptr);
}

// Calls f(key, value text) for every declared key whose value the settings hold.
template <class S, class F>
void visit_keys(std::span<const StageKey<S>> keys, const S& s, F&& f) {
  for (const auto& k : keys)
    if (k.value) f(k, k.value(s));
}

inline std::string type_text(KeyType t) {
  // In KeyType's order: number, integer, choice, vector, text, texts, table, number_or_auto,
  // custom.
  static constexpr std::string_view texts[] = {
      "number", "integer",          "string", "vector",
      "string", "array of strings", "table",  "`\"auto\"` or number",
      ""};
  static_assert(std::size(texts) == std::size_t(KeyType::custom) + 1);
  return std::string(texts[std::size_t(t)]);
}

// Units as messages write them (ASCII: "N.s/m", "kg/m^3") and as the docs do ("N·s/m", "kg/m³").
inline std::string unit_for_docs(std::string_view unit) {
  return key_detail::replace_all(
      key_detail::replace_all(key_detail::replace_all(unit, "N.s/m", "N·s/m"), "^2", "²"), "^3",
      "³");
}

// The declarations as the docs show them; defaults are the values in `defaults`.
template <class S>
std::vector<KeyInfo> describe_keys(std::span<const StageKey<S>> keys, const S& defaults) {
  using key_detail::number_text;
  std::vector<KeyInfo> out;
  for (const auto& k : keys) {
    KeyInfo i;
    i.key = k.key;
    i.type = k.info.type_doc.empty() ? type_text(k.type) : std::string(k.info.type_doc);
    i.unit = unit_for_docs(k.info.unit);
    if (!k.info.default_doc.empty())
      i.default_value = k.info.default_doc;
    else if (k.info.required)
      i.default_value = "required";
    else if (k.value) {
      // Texts as TOML writes them: choices, strings and an automatic value ("auto").
      const std::string value = k.value(defaults);
      const bool quoted = k.type == KeyType::choice || k.type == KeyType::text ||
                          (k.type == KeyType::number_or_auto && value == "auto");
      i.default_value =
          std::string(quoted ? "`\"" : "`").append(value).append(quoted ? "\"`" : "`");
    }
    if (!k.info.range_doc.empty()) {
      i.range = k.info.range_doc;
    } else if (k.type == KeyType::choice) {
      i.range = std::string("`").append(key_detail::replace_all(k.choices(), ", ", "`, `")) + "`";
    } else if (k.type == KeyType::number) {
      const std::string open = k.bound == Bound::positive ? "(" : "[";
      if (k.hi > k.lo)
        i.range = std::string(open)
                      .append(number_text(double(k.lo)))
                      .append(", ")
                      .append(number_text(double(k.hi))) +
                  "]";
      else
        i.range = k.bound == Bound::positive ? "> 0" : k.bound == Bound::non_negative ? ">= 0" : "";
    } else if (k.type == KeyType::integer) {
      i.range = number_text(double(k.lo)) + " to " + number_text(double(k.hi));
    }
    i.methods = k.info.methods.empty() ? "all" : std::string(k.info.methods);
    i.doc = k.info.doc;
    out.push_back(std::move(i));
  }
  return out;
}

// docs/scene-format.md's rows: | `key` | type | unit | default | range | [methods |] meaning |
inline std::vector<std::string> markdown_rows(std::span<const KeyInfo> keys, bool with_methods) {
  std::vector<std::string> rows;
  for (const auto& k : keys) {
    std::string r = "| `";
    r.append(k.key).append("` | ").append(k.type).append(" | ").append(k.unit).append(" | ");
    r.append(k.default_value).append(" | ").append(k.range).append(" | ");
    if (with_methods) r += k.methods + " | ";
    r += k.doc + " |";
    // Empty cells are written "| |", as the hand-written tables did.
    while (r.find("|  |") != std::string::npos) r = key_detail::replace_all(r, "|  |", "| |");
    rows.push_back(std::move(r));
  }
  return rows;
}

}  // namespace maille
