// The keys of [[listen]], [audio] and [[control]] (docs/sound.md), declared once
// (stage_keys.hpp): listen_table.cpp and control_table.cpp read them through these declarations
// and the docs' tables (scene-format.md, sound.md) are generated from them.
#pragma once

#include <span>

#include "maille/audio.hpp"
#include "maille/stage_keys.hpp"

namespace maille {

std::span<const StageKey<audio::Listener>> listen_keys();
std::span<const StageKey<audio::AudioSettings>> audio_keys();
// [[control]] (docs/sound.md, "Controls"): control_table.cpp reads them through these.
std::span<const StageKey<audio::Control>> control_keys();
std::span<const StageKey<audio::Excitation>> excite_keys();  // a control's `excite` table

}  // namespace maille
