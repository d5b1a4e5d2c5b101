// The keys of [[listen]] and [audio] (docs/sound.md), declared once (stage_keys.hpp):
// listen_table.cpp reads them through these declarations and docs/scene-format.md's tables are
// generated from them.
#pragma once

#include <span>

#include "maille/audio.hpp"
#include "maille/stage_keys.hpp"

namespace maille {

std::span<const StageKey<audio::Listener>> listen_keys();
std::span<const StageKey<audio::AudioSettings>> audio_keys();

}  // namespace maille
