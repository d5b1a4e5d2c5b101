// [[listen]] and [audio]: the sound of a scene (docs/sound.md), read against the built model.
#pragma once

#include "maille/audio.hpp"
#include "maille/model.hpp"
#include "toml_cursor.hpp"

namespace maille {

// Reads every [[listen]] table and the [audio] table of `top`; errors carry file, line,
// column and key like every other table's. [audio] without a [[listen]] is an error.
audio::AudioSpec read_audio_tables(TomlCursor& top, const Model& m);

}  // namespace maille
