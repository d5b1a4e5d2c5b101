#include "overrides.hpp"

#include <cctype>
#include <vector>

namespace maille {

namespace {

struct Segment {
  std::string key;
  std::optional<std::size_t> index;  // key[index]: an element of an array of tables
};

InputError error(const std::string& set, const std::string& key, const std::string& message) {
  std::string text = message;
  text.append(" (in --set ").append(set).append(")");
  return InputError{"--set", 0, 0, key, text};
}

// "flag[0].stiffness" -> {flag, 0}, {stiffness}; empty on a malformed path.
std::vector<Segment> split(const std::string& path) {
  std::vector<Segment> out;
  std::size_t i = 0;
  while (i <= path.size()) {
    const std::size_t dot = path.find('.', i);
    std::string part = path.substr(i, dot == std::string::npos ? std::string::npos : dot - i);
    Segment s;
    if (const auto open = part.find('['); open != std::string::npos) {
      if (part.back() != ']' || open + 2 > part.size() - 1) return {};
      const std::string digits = part.substr(open + 1, part.size() - open - 2);
      for (char c : digits)
        if (!std::isdigit(static_cast<unsigned char>(c))) return {};
      if (digits.empty() || digits.size() > 9) return {};
      s.index = std::stoul(digits);
      part = part.substr(0, open);
    }
    if (part.empty()) return {};
    for (char c : part)
      if (!(std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == '-')) return {};
    s.key = part;
    out.push_back(std::move(s));
    if (dot == std::string::npos) break;
    i = dot + 1;
  }
  return out;
}

// The value as TOML; a bare word that is not TOML is a string (broad_phase=brute).
toml::node_view<toml::node> parse_value(const std::string& text, toml::table& holder) {
  try {
    const std::string doc = "value = " + text;
    holder = toml::parse(std::string_view(doc), std::string_view("--set"));
  } catch (const toml::parse_error&) {
    holder = toml::table{};
    holder.insert("value", text);
  }
  return holder["value"];
}

}  // namespace

std::optional<InputError> apply_overrides(toml::table& root, std::span<const std::string> sets) {
  for (const std::string& set : sets) {
    const auto eq = set.find('=');
    if (eq == std::string::npos) return error(set, "", "expected KEY=VALUE");
    const std::string path = set.substr(0, eq);
    const std::vector<Segment> segments = split(path);
    if (segments.empty()) return error(set, path, "malformed key path (table.key, table[0].key)");
    toml::table* table = &root;
    std::string walked;
    for (std::size_t k = 0; k + 1 < segments.size(); ++k) {
      const Segment& s = segments[k];
      if (!walked.empty()) walked.push_back('.');
      walked.append(s.key);
      toml::node* node = table->get(s.key);
      if (s.index) {
        toml::array* array = node ? node->as_array() : nullptr;
        if (!array) return error(set, walked, "the scene has no [[" + s.key + "]] table to index");
        walked.append("[").append(std::to_string(*s.index)).append("]");
        if (*s.index >= array->size()) {
          std::string why = "index out of range: the scene has ";
          why.append(std::to_string(array->size()))
              .append(" [[")
              .append(s.key)
              .append("]] table(s)");
          return error(set, walked, why);
        }
        table = array->get(*s.index)->as_table();
        if (!table) return error(set, walked, "is not a table");
        continue;
      }
      if (!node) {  // a table the scene does not have yet ([self_collision] from the command line)
        table->insert(s.key, toml::table{});
        node = table->get(s.key);
      }
      table = node->as_table();
      if (!table) return error(set, walked, "is a value, not a table");
    }
    const Segment& last = segments.back();
    if (last.index) return error(set, path, "the last part of the path must be a key");
    toml::table holder;
    auto value = parse_value(set.substr(eq + 1), holder);
    table->insert_or_assign(last.key, *value.node());
  }
  return std::nullopt;
}

}  // namespace maille
