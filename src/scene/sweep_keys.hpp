// The keys of a sweep file (include/maille/sweep.hpp, docs/sweep.md), declared once: the reader
// (sweep_reader.cpp) names them in its unknown-key message and docs/sweep.md's table is
// generated from them. Each is read by the reader itself (custom): a sweep file is read with
// toml++ directly, its axes being any TOML value.
#pragma once

#include <span>
#include <string>

#include "maille/stage_keys.hpp"
#include "maille/sweep.hpp"

namespace maille {

std::span<const StageKey<Sweep>> sweep_keys();
// "scene, duration, [axes], [output]": the declared keys, tables in brackets.
std::string sweep_key_list();

}  // namespace maille
