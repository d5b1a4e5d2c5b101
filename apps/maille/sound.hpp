// `maille run --audio FILE.wav` and what `info` says of a scene's listeners (docs/sound.md).
#pragma once

#include <filesystem>
#include <iosfwd>
#include <string>

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

// `--audio FILE`'s checks, before anything is built: the scene must say what to listen to, from
// t = 0 (not `resuming`), within a WAV file's 4 GiB and the memory budget for `seconds` (the
// channels are held until the end, where the gain is set from their peaks). Says why on stderr
// and returns the exit code (exit_code::ok when none).
int check_audio(const std::string& scene, const audio::AudioSpec& spec, double seconds,
                bool resuming);
// What makes `--audio` name a file the run reads or writes otherwise (the scene, the output
// directory, its stats.csv, checkpoint.bin or a frame), or "" when it names none: a WAV written
// there would silently replace it.
std::string audio_clash(const std::filesystem::path& audio, const std::filesystem::path& scene,
                        const std::filesystem::path& out);

}  // namespace maille::app
