#include "maille/render/image.hpp"

#include <stb_image_write.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <stdexcept>
#include <system_error>
#include <vector>

#include "maille/io.hpp"

namespace maille::render {

void write_png(const Image& image, const std::filesystem::path& path) {
  if (image.width <= 0 || image.height <= 0 ||
      image.rgb.size() != static_cast<std::size_t>(image.width) * image.height * 3)
    throw std::invalid_argument("write_png: image size does not match its pixels");
  // Encoded in memory first (stb's file writer ignores fwrite and fclose errors), then written
  // under a temporary name with every write, the flush and the close checked, and renamed into
  // place only when whole. The temporary keeps the .png extension out of the final name only:
  // viewers and ffmpeg that glob for *.png never see a half-written file.
  std::vector<unsigned char> png;
  const auto append = [](void* context, void* data, int size) {
    auto* out = static_cast<std::vector<unsigned char>*>(context);
    const auto* bytes = static_cast<const unsigned char*>(data);
    out->insert(out->end(), bytes, bytes + size);
  };
  if (!stbi_write_png_to_func(append, &png, image.width, image.height, 3, image.rgb.data(),
                              image.width * 3))
    throw std::runtime_error("cannot encode " + path.string() + " as PNG");
  AtomicFile file(path);  // whole or not at all; a FIFO or a device written directly
  file.stream().write(reinterpret_cast<const char*>(png.data()), std::streamsize(png.size()));
  file.commit();
}

}  // namespace maille::render
