// RIFF WAVE, little-endian whatever the host:
//
//   "RIFF" size "WAVE"
//   "fmt " 16 | 18   format (1 PCM, 3 IEEE float), channels, rate, bytes/s, block align, bits
//                    (+ cbSize = 0 for float)
//   "fact" 4 frames  (float only: required for formats other than PCM)
//   "data" size      interleaved samples: frame 0 channel 0, frame 0 channel 1, ...
#include <algorithm>
#include <bit>
#include <cmath>
#include <cstring>
#include <fstream>
#include <stdexcept>

#include "maille/io.hpp"
#include "maille/wav.hpp"

namespace maille {

namespace {

void put_u16(std::ostream& out, std::uint32_t v) {
  const char b[2] = {char(v & 0xFF), char((v >> 8) & 0xFF)};
  out.write(b, 2);
}
void put_u32(std::ostream& out, std::uint32_t v) {
  const char b[4] = {char(v & 0xFF), char((v >> 8) & 0xFF), char((v >> 16) & 0xFF),
                     char((v >> 24) & 0xFF)};
  out.write(b, 4);
}

std::uint32_t get_u16(const unsigned char* p) {
  return std::uint32_t(p[0]) | std::uint32_t(p[1]) << 8;
}
std::uint32_t get_u32(const unsigned char* p) {
  return get_u16(p) | get_u16(p + 2) << 16;
}

}  // namespace

WavReport write_wav(const std::filesystem::path& path,
                    const std::vector<std::vector<float>>& channels, int rate,
                    audio::SampleFormat format, const std::vector<double>& gains) {
  if (channels.empty() || channels.size() > 65535)
    throw std::invalid_argument("a WAV file needs 1 to 65535 channels");
  const std::size_t frames = channels[0].size();
  for (const auto& ch : channels)
    if (ch.size() != frames) throw std::invalid_argument("WAV channels of unequal length");
  if (gains.size() != channels.size()) throw std::invalid_argument("one gain per WAV channel");
  const bool pcm = format == audio::SampleFormat::pcm16;
  const std::uint32_t bytes = pcm ? 2 : 4, nch = std::uint32_t(channels.size());
  const std::uint64_t data = std::uint64_t(frames) * nch * bytes;
  if (data > max_wav_data_bytes)
    throw std::invalid_argument("the audio would be " + std::to_string(data) +
                                " bytes, beyond the 4 GiB a WAV file can hold");
  WavReport report;
  report.frames = frames;
  for (const auto& ch : channels) {
    double peak = 0;
    for (const float x : ch) peak = std::max(peak, double(std::abs(x)));
    report.peak.push_back(peak);
  }

  AtomicFile file(path);
  std::ostream& out = file.stream();
  const std::uint32_t fmt_size = pcm ? 16 : 18, fact = pcm ? 0 : 12;
  out.write("RIFF", 4);
  put_u32(out, std::uint32_t(4 + 8 + fmt_size + fact + 8 + data));
  out.write("WAVE", 4);
  out.write("fmt ", 4);
  put_u32(out, fmt_size);
  put_u16(out, pcm ? 1 : 3);
  put_u16(out, nch);
  put_u32(out, std::uint32_t(rate));
  put_u32(out, std::uint32_t(rate) * nch * bytes);
  put_u16(out, nch * bytes);
  put_u16(out, bytes * 8);
  if (!pcm) {
    put_u16(out, 0);
    out.write("fact", 4);
    put_u32(out, 4);
    put_u32(out, std::uint32_t(frames));
  }
  out.write("data", 4);
  put_u32(out, std::uint32_t(data));
  // Interleaved, a block of frames at a time.
  std::vector<char> block;
  constexpr std::size_t kFrames = 4096;
  for (std::size_t f0 = 0; f0 < frames; f0 += kFrames) {
    const std::size_t f1 = std::min(frames, f0 + kFrames);
    block.clear();
    for (std::size_t f = f0; f < f1; ++f)
      for (std::size_t c = 0; c < nch; ++c) {
        const double y = gains[c] * double(channels[c][f]);
        std::uint32_t bits = 0;
        if (pcm) {
          if (std::abs(y) > 1) ++report.clipped;
          const auto s = static_cast<std::int16_t>(std::lround(std::clamp(y, -1.0, 1.0) * 32767));
          bits = std::uint16_t(s);
        } else {
          bits = std::bit_cast<std::uint32_t>(static_cast<float>(y));
        }
        for (std::uint32_t b = 0; b < bytes; ++b) block.push_back(char((bits >> (8 * b)) & 0xFF));
      }
    out.write(block.data(), std::streamsize(block.size()));
  }
  file.commit();
  return report;
}

WavData read_wav(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw std::runtime_error("cannot open " + path.string());
  std::vector<unsigned char> bytes((std::istreambuf_iterator<char>(in)),
                                   std::istreambuf_iterator<char>());
  const std::string where = path.string() + ": ";
  if (bytes.size() < 12 || std::memcmp(bytes.data(), "RIFF", 4) != 0 ||
      std::memcmp(bytes.data() + 8, "WAVE", 4) != 0)
    throw std::runtime_error(where + "not a RIFF WAVE file");
  WavData w;
  std::uint32_t format = 0, channels = 0, bits = 0;
  bool have_fmt = false;
  for (std::size_t at = 12; at + 8 <= bytes.size();) {
    const unsigned char* chunk = bytes.data() + at;
    const std::uint32_t size = get_u32(chunk + 4);
    const std::size_t body = at + 8;
    if (body + size > bytes.size()) throw std::runtime_error(where + "truncated chunk");
    if (std::memcmp(chunk, "fmt ", 4) == 0) {
      if (size < 16) throw std::runtime_error(where + "short fmt chunk");
      format = get_u16(chunk + 8);
      channels = get_u16(chunk + 10);
      w.rate = int(get_u32(chunk + 12));
      bits = get_u16(chunk + 22);
      have_fmt = true;
      if (!((format == 1 && bits == 16) || (format == 3 && bits == 32)))
        throw std::runtime_error(where + "unsupported format " + std::to_string(format) + " with " +
                                 std::to_string(bits) + " bits (16-bit PCM and 32-bit float are)");
      if (channels == 0) throw std::runtime_error(where + "no channel");
      w.format = format == 1 ? audio::SampleFormat::pcm16 : audio::SampleFormat::float32;
    } else if (std::memcmp(chunk, "data", 4) == 0) {
      if (!have_fmt) throw std::runtime_error(where + "data before fmt");
      const std::uint32_t b = bits / 8;
      if (size % (b * channels) != 0) throw std::runtime_error(where + "truncated data");
      const std::size_t frames = size / (b * channels);
      w.channels.assign(channels, std::vector<float>(frames));
      const unsigned char* p = bytes.data() + body;
      for (std::size_t f = 0; f < frames; ++f)
        for (std::uint32_t c = 0; c < channels; ++c, p += b)
          w.channels[c][f] = b == 2 ? float(std::int16_t(std::uint16_t(get_u16(p)))) / 32767.0f
                                    : std::bit_cast<float>(get_u32(p));
      return w;
    }
    at = body + size + (size & 1);  // chunks are padded to even sizes
  }
  throw std::runtime_error(where + (have_fmt ? "no data chunk" : "no fmt chunk"));
}

}  // namespace maille
