// `maille run --audio FILE.wav` and what `info` says of a scene's listeners (docs/sound.md).
#pragma once

#include <filesystem>
#include <iosfwd>

#include "maille/audio.hpp"
#include "maille/wav.hpp"

namespace maille::app {

// Lines for `maille info`: one per listener, then the rate, format, gain and sampling plan.
void describe_audio(std::ostream& out, const audio::AudioSpec& spec, double step);

// Bytes of a WAV of `seconds` of the spec's channels: refused (usage) beyond the RIFF limit.
std::uint64_t planned_wav_bytes(const audio::AudioSpec& spec, double seconds);
// The bytes a recording of `seconds` holds in memory until it is written: its float samples
// (audio::Recorder keeps every channel whole; the WAV is written block by block from them).
std::uint64_t planned_audio_memory_bytes(const audio::AudioSpec& spec, double seconds);

// Finishes the recorder, writes the WAV atomically and prints the summary line (channels, rate,
// format, samples, gain, sampling). Throws std::runtime_error when the file cannot be written.
WavReport write_sound(audio::Recorder& recorder, const std::filesystem::path& path);

}  // namespace maille::app
