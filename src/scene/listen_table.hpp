// [[listen]] and [audio]: the sound of a scene (docs/sound.md), read against the built model.
#pragma once

#include "maille/audio.hpp"
#include "maille/model.hpp"
#include "toml_cursor.hpp"

namespace maille {

// Reads every [[listen]] table and the [audio] table of `top`; errors carry file, line,
// column and key like every other table's. [audio] without a [[listen]] is an error.
// [[control]] tables too (control_table.cpp).
audio::AudioSpec read_audio_tables(TomlCursor& top, const Model& m);

// The point table `t` names by `point` ("name", "group:index", an index) or `group` + `index`;
// its label as written.
std::uint32_t listened_point(TomlCursor& t, const Model& m, std::string& label);

// Every [[control]] table of `top` (control_table.cpp).
std::vector<audio::Control> read_control_tables(TomlCursor& top, const Model& m);

}  // namespace maille
