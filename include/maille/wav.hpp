// WAV files (RIFF WAVE): 16-bit PCM or 32-bit IEEE float, one channel per listener, written
// whole or not at all (AtomicFile: "<name>.tmp" renamed when complete).
#pragma once

#include <cstdint>
#include <filesystem>
#include <vector>

#include "maille/audio.hpp"

namespace maille {

struct WavReport {
  std::uint64_t frames = 0;   // samples per channel
  std::uint64_t clipped = 0;  // PCM samples beyond full scale, set to +-1 (a fixed gain)
  std::vector<double> peak;   // per channel, the largest |value| before the gain
};

// Largest data chunk a RIFF file can describe (its sizes are 32-bit), bytes.
constexpr std::uint64_t max_wav_data_bytes = 0xFFFFFFFFull - 64;

// Writes channels (equal lengths) at `rate` Hz, channel c with gains[c]: PCM16 as
// round(32767 clamp(gain x value, -1, 1)), float32 as gain x value (not clipped). Throws
// std::runtime_error naming the file and the cause (a write, flush, close or rename that failed;
// the file left as it was) and std::invalid_argument for channels of unequal length or data beyond
// the RIFF limit.
WavReport write_wav(const std::filesystem::path& path,
                    const std::vector<std::vector<float>>& channels, int rate,
                    audio::SampleFormat format, const std::vector<double>& gains);

struct WavData {
  int rate = 0;
  audio::SampleFormat format = audio::SampleFormat::pcm16;
  std::vector<std::vector<float>> channels;  // PCM16 as value / 32767, float32 as stored
};

// Reads a file written by write_wav (or any PCM16 / float32 WAV). Throws std::runtime_error
// saying what is wrong ("not a RIFF WAVE file", "unsupported format 2", "truncated data").
WavData read_wav(const std::filesystem::path& path);

}  // namespace maille
