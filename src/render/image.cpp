#include "maille/render/image.hpp"

#include <stb_image_write.h>

#include <stdexcept>
#include <system_error>

namespace maille::render {

void write_png(const Image& image, const std::filesystem::path& path) {
  if (image.width <= 0 || image.height <= 0 ||
      image.rgb.size() != static_cast<std::size_t>(image.width) * image.height * 3)
    throw std::invalid_argument("write_png: image size does not match its pixels");
  // The temporary keeps the .png extension out of the final name only: viewers and ffmpeg that
  // glob for *.png never see a half-written file.
  const std::filesystem::path tmp = path.string() + ".tmp";
  if (!stbi_write_png(tmp.c_str(), image.width, image.height, 3, image.rgb.data(),
                      image.width * 3)) {
    std::error_code ignored;
    std::filesystem::remove(tmp, ignored);
    throw std::runtime_error("cannot write " + path.string());
  }
  std::error_code ec;
  std::filesystem::rename(tmp, path, ec);
  if (ec) throw std::runtime_error("cannot write " + path.string() + ": " + ec.message());
}

}  // namespace maille::render
