// Scene files for the viewer: the picker's list and the watch that reloads a scene when its
// file changes on disk.
#pragma once

#include <filesystem>
#include <optional>
#include <vector>

namespace maille::viewer {

// The .toml files of `directory`, sorted by name; empty when it cannot be read.
std::vector<std::filesystem::path> list_scenes(const std::filesystem::path& directory);

// Polls a file's modification time and size. changed() is true once per change, and only after
// the file has stayed the same for two polls in a row, so that an editor's save in several
// writes is reloaded once, whole.
class FileWatch {
 public:
  FileWatch() = default;
  explicit FileWatch(std::filesystem::path file);
  bool changed();
  const std::filesystem::path& file() const { return file_; }

 private:
  struct Stamp {
    std::filesystem::file_time_type time;
    std::uintmax_t size = 0;
    bool operator==(const Stamp&) const = default;
  };
  std::optional<Stamp> stamp() const;
  std::filesystem::path file_;
  std::optional<Stamp> loaded_, seen_;
};

}  // namespace maille::viewer
