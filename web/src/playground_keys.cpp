// The page's sliders (Playground::slider_keys): generated from the engine's declarations of the
// scene's keys, so that every key a table of the scene declares gets a slider with its
// documented range, as `maille info --keys` and docs/scene-format.md list them
// (declared_tables: the stage tables' StageKey declarations, [fields.wind],
// [simulation.implicit], [[contact]]: slider_table); and the other numbers of the text
// (builders, [simulation], [fields]), bounded by the link kinds' ParamField of that name where
// there is one.
#include <cstdio>
#include <cstdlib>
#include <set>

#define TOML_HEADER_ONLY 0
#include <toml++/toml.h>

#include "maille/link_registry.hpp"
#include "maille/scene.hpp"
#include "maille/stage_registry.hpp"
#include "playground.hpp"

namespace maille::web {

namespace {

std::string unquoted(std::string s) {
  std::erase(s, '`');
  std::erase(s, '"');
  return s;
}

bool number_of(const std::string& text, double& out) {
  const std::string s = unquoted(text);
  if (s.empty()) return false;
  char* end = nullptr;
  out = std::strtod(s.c_str(), &end);
  return end && *end == '\0';
}

// A documented range: "[lo, hi]", "(lo, hi]" (maybe followed by a note), "lo to hi", "> 0",
// ">= 0" (describe_keys).
void read_range(const std::string& range, SliderKey& k) {
  k.range = range;
  if (range == "> 0") {
    k.bound = "positive";
    return;
  }
  if (range == ">= 0") {
    k.bound = "non_negative";
    return;
  }
  double lo = 0, hi = 0;
  const auto close = range.find(']');  // "[0, 1e6] (0: the default)": the interval first
  if (!range.empty() && (range[0] == '[' || range[0] == '(') && close != std::string::npos) {
    const auto comma = range.find(',');
    if (comma != std::string::npos && comma < close && number_of(range.substr(1, comma - 1), lo) &&
        number_of(range.substr(comma + 2, close - comma - 2), hi)) {
      k.lo = lo, k.hi = hi, k.lo_open = range[0] == '(';
      k.bound = k.lo_open && lo == 0 ? "positive" : lo >= 0 ? "non_negative" : "";
    }
    return;
  }
  if (const auto to = range.find(" to "); to != std::string::npos)
    if (number_of(range.substr(0, to), lo) && number_of(range.substr(to + 4), hi))
      k.lo = lo, k.hi = hi, k.bound = lo > 0 ? "positive" : lo >= 0 ? "non_negative" : "";
}

bool uses(const std::string& methods, const std::string& method) {
  if (methods == "all" || method.empty()) return true;
  std::size_t at = 0;
  while (at <= methods.size()) {
    const std::size_t end = std::min(methods.find(", ", at), methods.size());
    if (methods.compare(at, end - at, method) == 0) return true;
    at = end + 2;
  }
  return false;
}

// The declared keys of one instance of a table (`prefix`: its --set path).
void table_sliders(const DeclaredTable& t, const toml::table* written, const std::string& prefix,
                   std::vector<SliderKey>& out) {
  std::string method;
  for (const KeyInfo& k : t.keys)
    if (k.key == "method") method = unquoted(k.default_value);
  if (written)
    if (const auto m = (*written)["method"].value<std::string>()) method = *m;
  for (const KeyInfo& info : t.keys) {
    if (info.type != "number" && info.type != "integer") continue;
    if (!uses(info.methods, method)) continue;  // setting it would be an error for this method
    SliderKey k;
    k.key = prefix + "." + info.key;
    k.declared = true;
    k.integer = info.type == "integer";
    k.unit = info.unit;
    k.doc = info.doc;
    read_range(info.range, k);
    const toml::node* node = written ? written->get(info.key) : nullptr;
    if (node && node->is_number()) {
      k.value = node->value<double>().value_or(0);
      k.written = true;
    } else if (!number_of(info.default_value, k.value)) {
      continue;  // no number to start from (required, or derived from another key)
    }
    out.push_back(std::move(k));
  }
}

// The tables whose declared keys get sliders with their declared ranges: the stages' tables and
// [fields.wind], [simulation.implicit], [[contact]], whose every key a live set() takes alone at
// either end of its range. The builders', [simulation]'s and [fields]' keys are bounded together
// by the model they make (a flag's width by its origin and the 1e6 m box, its mass by the mass
// per point, a step by the duration): their numbers get the sliders of the numbers the text
// writes, below.
bool slider_table(const std::string& table, const StageRegistry& registry) {
  for (const auto& e : registry.entries())
    if (table == (e.array ? "[[" + e.table + "]]" : "[" + e.table + "]")) return true;
  return table == "[fields.wind]" || table == "[simulation.implicit]" || table == "[[contact]]";
}

Bound link_field_bound(const std::string& name, bool& found) {
  static const LinkKindRegistry kinds = LinkKindRegistry::with_builtins();
  for (const auto& e : kinds.entries())
    for (const ParamInfo& f : e.fields)
      if (f.name == name) {
        found = true;
        return f.bound;
      }
  found = false;
  return Bound::any;
}

}  // namespace

std::vector<SliderKey> Playground::slider_keys() const {
  std::vector<SliderKey> out;
  if (!sim_) return out;
  toml::table root;
  try {
    root = toml::parse(text_, source_name_);
  } catch (const toml::parse_error&) {
    return out;
  }
  static const StageRegistry registry = StageRegistry::with_builtins();
  for (const DeclaredTable& t : declared_tables(registry)) {
    if (!slider_table(t.table, registry)) continue;
    const bool array = t.table.rfind("[[", 0) == 0;
    const std::string path = t.table.substr(array ? 2 : 1, t.table.size() - (array ? 4 : 2));
    const toml::node* node = root.at_path(path).node();
    if (!node) continue;  // the scene has no such table
    if (array) {
      if (const toml::array* a = node->as_array())
        for (std::size_t i = 0; i < a->size(); ++i)
          table_sliders(t, a->get(i)->as_table(), path + "[" + std::to_string(i) + "]", out);
    } else {
      table_sliders(t, node->as_table(), path, out);
    }
  }
  // A declared key the text does not write may still be refused for this table (a torus's
  // tube on a sphere): read the scene with it set to its default, and keep it only if accepted.
  std::erase_if(out, [&](const SliderKey& k) {
    if (k.written) return false;
    std::vector<std::string> overrides = overrides_;
    char value[32];
    std::snprintf(value, sizeof value, "%.17g", k.value);
    overrides.push_back(k.key + "=" + value);
    return !parse_scene(text_, source_name_, LinkKindRegistry::with_builtins(), registry, overrides)
                .ok();
  });
  std::set<std::string> covered;
  for (const SliderKey& k : out) covered.insert(k.key);
  // The other numbers the text writes (with the overrides in force).
  for (const DeclaredKey& d : declared_keys()) {
    if (covered.count(d.key)) {
      for (SliderKey& k : out)
        if (k.key == d.key) k.value = d.value, k.written = true;
      continue;
    }
    SliderKey k;
    k.key = d.key;
    k.value = d.value;
    k.integer = d.integer;
    k.written = true;
    bool found = false;
    const std::string leaf = d.key.substr(d.key.rfind('.') + 1);
    const Bound b = link_field_bound(leaf, found);
    if (found)
      k.bound = b == Bound::positive ? "positive" : b == Bound::non_negative ? "non_negative" : "";
    out.push_back(std::move(k));
  }
  return out;
}

}  // namespace maille::web
