// `--set KEY=VALUE`: overrides of scene keys by their dotted path, applied to the parsed TOML
// before the scene is read, so that they go through exactly the same validation (and an error
// in one names it: "--set:1:..: key 'flag[0].stiffness': ...").
//
//   simulation.step=2e-4            a key of a table (created when absent: [self_collision]...)
//   flag[0].stiffness=800           a key of the first [[flag]] table
//   self_collision.broad_phase=brute  a bare word is a string; "quoted" too; numbers, booleans,
//   fields.gravity=[0,-1.6,0]         arrays and inline tables are TOML values
#pragma once

#include <optional>
#include <span>
#include <string>

#define TOML_HEADER_ONLY 0
#include <toml++/toml.h>

#include "maille/result.hpp"

namespace maille {

// Applies every override in order; the first malformed one (no '=', an empty or malformed path,
// an index out of range, a path through a value that is not a table) is returned as an error.
std::optional<InputError> apply_overrides(toml::table& root, std::span<const std::string> sets);

}  // namespace maille
