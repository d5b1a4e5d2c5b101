#include "maille/render/frame_sink.hpp"

#include <fcntl.h>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <csignal>
#include <cstdio>
#include <cstring>
#include <stdexcept>
#include <vector>

#include "maille/io.hpp"

extern char** environ;

namespace maille::render {

namespace {

class PngSequence final : public FrameSink {
 public:
  explicit PngSequence(std::filesystem::path dir) : dir_(std::move(dir)) {
    std::error_code ec;
    std::filesystem::create_directories(dir_, ec);
    if (ec) throw std::runtime_error("cannot create " + dir_.string() + ": " + ec.message());
  }
  void write(const Image& frame) override {
    char name[32];
    std::snprintf(name, sizeof name, "frame_%06d.png", count_++);
    write_png(frame, dir_ / name);
  }
  void finish() override {}
  std::string describe() const override {
    return std::to_string(count_) + " PNG frames in " + dir_.string();
  }

 private:
  std::filesystem::path dir_;
  int count_ = 0;
};

// Keeps only the last frame and writes it on finish(): a still of the end of the run.
class PngStill final : public FrameSink {
 public:
  explicit PngStill(std::filesystem::path file) : file_(std::move(file)) {}
  void write(const Image& frame) override { last_ = frame; }
  void finish() override {
    if (last_.rgb.empty()) throw std::runtime_error("no frame rendered for " + file_.string());
    write_png(last_, file_);
  }
  std::string describe() const override { return file_.string(); }

 private:
  std::filesystem::path file_;
  Image last_;
};

// The file an MP4 replaces: a symbolic link is followed (the link kept). MP4 seeks back to
// write its index, so a FIFO or a device, which output_target would write into, is refused
// rather than renamed over.
std::filesystem::path video_file(const std::filesystem::path& file) {
  const OutputTarget target = output_target(file);
  if (target.direct)
    throw std::runtime_error("cannot write " + file.string() +
                             ": an MP4 video needs a regular file (this is a FIFO or a device)");
  return target.file;
}

// ffmpeg reads raw RGB frames on its standard input. It is started with posix_spawn (no shell,
// so file names need no quoting); a broken pipe (ffmpeg died) turns into an error on write
// instead of killing the process with SIGPIPE.
class FfmpegVideo final : public FrameSink {
 public:
  FfmpegVideo(std::filesystem::path file, int width, int height, double fps)
      : file_(video_file(file)), tmp_(file_.string() + ".tmp"), width_(width), height_(height) {
    if (width % 2 || height % 2)
      throw std::runtime_error("MP4 needs an even width and height (got " + std::to_string(width) +
                               "x" + std::to_string(height) + ")");
    std::signal(SIGPIPE, SIG_IGN);
    int fds[2];
    if (pipe2(fds, O_CLOEXEC) != 0) throw std::runtime_error("cannot create a pipe to ffmpeg");
    const std::string size = std::to_string(width) + "x" + std::to_string(height);
    const std::string rate = std::to_string(fps);
    std::vector<std::string> args = {
        "ffmpeg",   "-hide_banner", "-loglevel", "error",      "-y",   "-f",   "rawvideo",
        "-pix_fmt", "rgb24",        "-s",        size,         "-r",   rate,   "-i",
        "-",        "-c:v",         "libx264",   "-preset",    "fast", "-crf", "20",
        "-pix_fmt", "yuv420p",      "-movflags", "+faststart", "-f",   "mp4",  tmp_.string()};
    std::vector<char*> argv;
    for (auto& a : args) argv.push_back(a.data());
    argv.push_back(nullptr);
    posix_spawn_file_actions_t actions;
    posix_spawn_file_actions_init(&actions);
    posix_spawn_file_actions_adddup2(&actions, fds[0], STDIN_FILENO);
    // ffmpeg gets its own process group: Ctrl-C on the terminal (SIGINT to the foreground
    // group) reaches maille only, which stops rendering and then closes the pipe, so ffmpeg
    // finishes the video with the frames made so far.
    posix_spawnattr_t attributes;
    posix_spawnattr_init(&attributes);
    posix_spawnattr_setflags(&attributes, POSIX_SPAWN_SETPGROUP);
    posix_spawnattr_setpgroup(&attributes, 0);
    const int rc = posix_spawnp(&pid_, "ffmpeg", &actions, &attributes, argv.data(), environ);
    posix_spawnattr_destroy(&attributes);
    posix_spawn_file_actions_destroy(&actions);
    close(fds[0]);
    if (rc != 0) {
      close(fds[1]);
      throw std::runtime_error(std::string("cannot start ffmpeg (") + std::strerror(rc) +
                               "); install it (Debian: apt-get install ffmpeg) or write PNG "
                               "frames to a directory");
    }
    pipe_ = fds[1];
  }

  ~FfmpegVideo() override {
    if (pipe_ >= 0) {  // not finished: stop ffmpeg and leave nothing behind
      close(pipe_);
      wait_for_ffmpeg();
      std::error_code ignored;
      std::filesystem::remove(tmp_, ignored);
    }
  }

  void write(const Image& frame) override {
    if (frame.width != width_ || frame.height != height_)
      throw std::runtime_error("frame size differs from the video's");
    const std::uint8_t* p = frame.rgb.data();
    std::size_t left = frame.rgb.size();
    while (left > 0) {
      const ssize_t n = ::write(pipe_, p, left);
      if (n < 0 && errno == EINTR) continue;
      if (n <= 0)
        throw std::runtime_error("ffmpeg stopped reading frames for " + file_.string() + " (" +
                                 std::strerror(n < 0 ? errno : EPIPE) + ")");
      p += n;
      left -= static_cast<std::size_t>(n);
    }
  }

  void finish() override {
    close(pipe_);
    pipe_ = -1;
    const int status = wait_for_ffmpeg();
    if (!WIFEXITED(status) || WEXITSTATUS(status) != 0) {
      std::error_code ignored;
      std::filesystem::remove(tmp_, ignored);
      throw std::runtime_error(
          "ffmpeg failed to encode " + file_.string() +
          (WIFEXITED(status) ? " (exit status " + std::to_string(WEXITSTATUS(status)) + ")"
                             : " (killed by signal " + std::to_string(WTERMSIG(status)) + ")"));
    }
    std::error_code ec;
    std::filesystem::rename(tmp_, file_, ec);
    if (ec) throw std::runtime_error("cannot write " + file_.string() + ": " + ec.message());
  }

  std::string describe() const override { return file_.string(); }

 private:
  int wait_for_ffmpeg() {
    int status = 0;
    while (waitpid(pid_, &status, 0) < 0 && errno == EINTR) {
    }
    return status;
  }

  std::filesystem::path file_, tmp_;
  int width_, height_;
  pid_t pid_ = -1;
  int pipe_ = -1;
};

}  // namespace

std::unique_ptr<FrameSink> png_sequence(const std::filesystem::path& directory) {
  return std::make_unique<PngSequence>(directory);
}

std::unique_ptr<FrameSink> png_still(const std::filesystem::path& file) {
  return std::make_unique<PngStill>(file);
}

std::unique_ptr<FrameSink> ffmpeg_video(const std::filesystem::path& file, int width, int height,
                                        double fps) {
  return std::make_unique<FfmpegVideo>(file, width, height, fps);
}

}  // namespace maille::render
