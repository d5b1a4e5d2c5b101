// Where rendered frames go: numbered PNG files in a directory, or an MP4 video encoded by ffmpeg.
// Both write whole files only: a video is encoded under a temporary name and renamed by
// finish(); a sink destroyed before finish() removes what it started.
#pragma once

#include <filesystem>
#include <memory>
#include <string>

#include "maille/render/image.hpp"

namespace maille::render {

class FrameSink {
 public:
  virtual ~FrameSink() = default;
  // Throws std::runtime_error when the frame cannot be written.
  virtual void write(const Image& frame) = 0;
  virtual void finish() = 0;  // completes the output; throws std::runtime_error on failure
  virtual std::string describe() const = 0;  // where the frames went, for messages
};

// frame_000000.png, frame_000001.png, ... in `directory` (created when missing).
std::unique_ptr<FrameSink> png_sequence(const std::filesystem::path& directory);
// One PNG file holding the last frame written.
std::unique_ptr<FrameSink> png_still(const std::filesystem::path& file);
// An H.264 MP4 (yuv420p, so width and height must be even) of width x height frames at `fps`
// frames per second, encoded by the `ffmpeg` program found on PATH, fed raw RGB through a pipe.
// Throws std::runtime_error when ffmpeg cannot be started or the size is odd.
std::unique_ptr<FrameSink> ffmpeg_video(const std::filesystem::path& file, int width, int height,
                                        double fps);

}  // namespace maille::render
