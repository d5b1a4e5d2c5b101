// An 8-bit RGB image in memory, as read back from the renderer, and its PNG file.
#pragma once

#include <cstdint>
#include <filesystem>
#include <vector>

namespace maille::render {

struct Image {
  int width = 0, height = 0;      // pixels
  std::vector<std::uint8_t> rgb;  // [height][width][3], rows from the top

  struct Pixel {
    std::uint8_t r, g, b;
  };
  Pixel at(int x, int y) const {
    const auto i = (static_cast<std::size_t>(y) * static_cast<std::size_t>(width) +
                    static_cast<std::size_t>(x)) *
                   3;
    return {rgb[i], rgb[i + 1], rgb[i + 2]};
  }
};

// Writes `image` as PNG, whole or not at all (a temporary file renamed when complete). Throws
// std::runtime_error naming the file when it cannot be written.
void write_png(const Image& image, const std::filesystem::path& path);

}  // namespace maille::render
