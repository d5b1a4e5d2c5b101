// A guard in front of toml++ 3.3 (Debian 12's version), whose whitespace test reaches
// __builtin_unreachable() (undefined behaviour) for non-ASCII code points in U+00A1..U+0499 and
// U+2C8E..U+3087 wherever the parser looks for whitespace: outside strings and comments, and
// after a line-ending backslash in a multi-line basic string (upstream issues marzer/tomlplusplus
// #190 and #295, fixed after 3.4). Found by fuzz/fuzz_scene.cpp.
#pragma once

#include <optional>
#include <string>
#include <string_view>

namespace maille {

struct TomlHazard {
  int line = 0, column = 0;  // 1-based; column in bytes
  const char* message = "";
};

// The first place in `text` where toml++ could hit that bug, or nothing. Non-ASCII text outside
// strings and comments is invalid TOML anyway; the only valid TOML it refuses is a non-ASCII
// character right after a line-ending backslash in a """multi-line""" string.
std::optional<TomlHazard> find_toml_hazard(std::string_view text);

// "TOML syntax: " and toml++'s description of a parse error at `line` (1-based) of `text`, with
// one of toml++ 3.3's messages mended: a key defined twice is echoed garbled ("cannot redefine
// existing integer '"a a b" '" for "a b"), so the key is taken from the source line instead.
std::string toml_syntax_message(std::string_view text, int line, std::string_view description);

}  // namespace maille
