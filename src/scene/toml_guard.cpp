#include "toml_guard.hpp"

#include <algorithm>
#include <cstddef>

namespace maille {

namespace {

bool non_ascii(char c) {
  return static_cast<unsigned char>(c) >= 0x80;
}

TomlHazard at(std::string_view text, std::size_t offset, const char* message) {
  const std::string_view before = text.substr(0, offset);
  const std::size_t newline = before.rfind('\n');
  const std::size_t line_start = newline == std::string_view::npos ? 0 : newline + 1;
  const auto line = std::count(before.begin(), before.end(), '\n');
  return {static_cast<int>(line) + 1, static_cast<int>(offset - line_start) + 1, message};
}

bool string_may_start(char previous) {
  return previous == '\n' || previous == '=' || previous == '[' || previous == ',' ||
         previous == '{';
}

}  // namespace

// A small lexer that knows only what toml++ treats as text: comments (# to the end of the line)
// and the four kinds of strings. Everything else must be ASCII. A quote opens a string only
// where a key or a value may begin (after a newline, '=', '[', ',' or '{'); anywhere else the
// document is invalid and toml++ may be scanning a bad token through it.
std::optional<TomlHazard> find_toml_hazard(std::string_view text) {
  enum class In { code, comment, basic, literal, multi_basic, multi_literal };
  In in = In::code;
  char previous = '\n';  // the last character in code other than a space or tab
  const std::size_t n = text.size();
  auto starts = [&](std::size_t i, std::string_view s) { return text.substr(i, s.size()) == s; };
  std::size_t i = starts(0, "\xEF\xBB\xBF") ? 3 : 0;  // a UTF-8 byte order mark, which toml++ skips
  while (i < n) {
    const char c = text[i];
    switch (in) {
      case In::code:
        if (non_ascii(c)) return at(text, i, "non-ASCII character outside a string or comment");
        if (c == '#') {
          in = In::comment;
        } else if ((c == '"' || c == '\'') && !string_may_start(previous)) {
          // Not a string for toml++ either: it is inside a bad token (`1e3'...`), which toml++
          // keeps scanning, testing each character for whitespace. Stay in code.
        } else if (starts(i, "\"\"\"")) {
          in = In::multi_basic;
          i += 3;
          continue;
        } else if (starts(i, "'''")) {
          in = In::multi_literal;
          i += 3;
          continue;
        } else if (c == '"') {
          in = In::basic;
        } else if (c == '\'') {
          in = In::literal;
        }
        if (c != ' ' && c != '\t' && c != '\r') previous = c;
        break;
      case In::comment:
        if (c == '\n') in = In::code, previous = c;
        break;
      case In::basic:
        if (c == '\\') {
          i += 2;  // the escaped character (toml++ reports a bad escape itself)
          continue;
        }
        if (c == '"' || c == '\n') in = In::code, previous = c;
        break;
      case In::literal:
        if (c == '\'' || c == '\n') in = In::code, previous = c;
        break;
      case In::multi_basic:
        if (c == '\\') {
          // A line-ending backslash trims the whitespace that follows, newlines included:
          // toml++ tests each character for whitespace up to the first that is not.
          std::size_t j = i + 1;
          while (j < n && (text[j] == ' ' || text[j] == '\t' || text[j] == '\n' || text[j] == '\r'))
            ++j;
          if (j < n && non_ascii(text[j]))
            return at(text, j,
                      "non-ASCII character after a backslash in a multi-line string "
                      "(not supported by the TOML library)");
          i = j > i + 1 ? j : i + 2;
          continue;
        }
        if (starts(i, "\"\"\"")) {
          in = In::code, previous = '"';
          i += 3;
          while (i < n && text[i] == '"') ++i;  // up to two quotes may end the content
          continue;
        }
        break;
      case In::multi_literal:
        if (starts(i, "'''")) {
          in = In::code, previous = '\'';
          i += 3;
          while (i < n && text[i] == '\'') ++i;
          continue;
        }
        break;
    }
    ++i;
  }
  return std::nullopt;
}

std::string toml_syntax_message(std::string_view text, int line, std::string_view description) {
  const std::string plain = "TOML syntax: " + std::string(description);
  if (description.find("cannot redefine existing") == std::string_view::npos || line < 1)
    return plain;
  std::size_t start = 0;
  for (int l = 1; l < line; ++l) {
    start = text.find('\n', start);
    if (start == std::string_view::npos) return plain;
    ++start;
  }
  std::string_view source = text.substr(start, text.find('\n', start) - start);
  const auto trim = [](std::string_view v) {
    while (!v.empty() && (v.front() == ' ' || v.front() == '\t')) v.remove_prefix(1);
    while (!v.empty() && (v.back() == ' ' || v.back() == '\t' || v.back() == '\r'))
      v.remove_suffix(1);
    return v;
  };
  source = trim(source);
  // A table header ([a.b], [[a]]) names itself; a key-value pair, what precedes its '='
  // (outside quotes: a quoted key may hold one).
  std::string_view key = source;
  if (!source.starts_with('[')) {
    char quote = 0;
    std::size_t eq = std::string_view::npos;
    for (std::size_t i = 0; i < source.size() && eq == std::string_view::npos; ++i) {
      const char c = source[i];
      if (quote) {
        if (c == '\\' && quote == '"')
          ++i;
        else if (c == quote)
          quote = 0;
      } else if (c == '"' || c == '\'') {
        quote = c;
      } else if (c == '=') {
        eq = i;
      }
    }
    if (eq == std::string_view::npos) return plain;
    key = trim(source.substr(0, eq));
  }
  if (key.empty()) return plain;
  return "TOML syntax: " + std::string(key) +
         " is defined twice (a key or a table may be given once in its table)";
}

}  // namespace maille
