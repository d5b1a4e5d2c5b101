// Whether a recording is a stretch of a reference, sample for sample (tests/cli_play_jack.sh:
// what a JACK client recorded of `maille play` against `maille run --audio` of the same scene).
//
//   wav_match REFERENCE.wav RECORDING.wav MIN_FRAMES
// The recording started while the player was already playing: the offset d where
// recording[i] == reference[i + d] for the first 64 frames is found, then every overlapping
// frame of every channel is compared, bit for bit. Exit 0 when all of them match and at least
// MIN_FRAMES overlap; prints the offset, the frames compared and the first mismatch.
#include <cstdio>
#include <cstdlib>
#include <string>

#include "maille/wav.hpp"

int main(int argc, char** argv) {
  if (argc != 4) {
    std::fprintf(stderr, "usage: wav_match REFERENCE.wav RECORDING.wav MIN_FRAMES\n");
    return 2;
  }
  const maille::WavData ref = maille::read_wav(argv[1]);
  const maille::WavData rec = maille::read_wav(argv[2]);
  const std::size_t min_frames = std::stoul(argv[3]);
  if (ref.channels.size() != rec.channels.size() || ref.channels.empty()) {
    std::fprintf(stderr, "wav_match: %zu channels against %zu\n", ref.channels.size(),
                 rec.channels.size());
    return 1;
  }
  const auto& a = ref.channels[0];
  const auto& b = rec.channels[0];
  // The recording's first 64 frames, with something in them, located in the reference.
  std::size_t start = 0;
  while (start < b.size() && b[start] == 0.0f) ++start;
  constexpr std::size_t kWindow = 64;
  if (start + kWindow > b.size()) {
    std::fprintf(stderr, "wav_match: the recording is silent\n");
    return 1;
  }
  long offset = -1;
  for (std::size_t d = 0; d + kWindow <= a.size() && offset < 0; ++d) {
    std::size_t k = 0;
    while (k < kWindow && a[d + k] == b[start + k]) ++k;
    if (k == kWindow) offset = long(d) - long(start);
  }
  if (offset < 0) {
    std::fprintf(stderr, "wav_match: the recording's frames %zu.. are nowhere in the reference\n",
                 start);
    return 1;
  }
  std::size_t compared = 0;
  for (std::size_t i = 0; i < b.size(); ++i) {
    const long j = long(i) + offset;
    if (j < 0 || std::size_t(j) >= a.size()) continue;
    for (std::size_t c = 0; c < ref.channels.size(); ++c)
      if (ref.channels[c][std::size_t(j)] != rec.channels[c][i]) {
        std::printf(
            "offset %ld: MISMATCH at recorded frame %zu channel %zu: %.9g against %.9g "
            "(after %zu equal frames)\n",
            offset, i, c, double(rec.channels[c][i]), double(ref.channels[c][std::size_t(j)]),
            compared);
        return 1;
      }
    ++compared;
  }
  std::printf("offset %ld: %zu frames x %zu channels equal, bit for bit\n", offset, compared,
              ref.channels.size());
  return compared >= min_frames ? 0 : 1;
}
