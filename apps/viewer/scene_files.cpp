#include "scene_files.hpp"

#include <algorithm>

namespace maille::viewer {

std::vector<std::filesystem::path> list_scenes(const std::filesystem::path& directory) {
  std::vector<std::filesystem::path> scenes;
  std::error_code ec;
  for (const auto& entry : std::filesystem::directory_iterator(directory, ec))
    if (entry.is_regular_file(ec) && entry.path().extension() == ".toml")
      scenes.push_back(entry.path());
  std::sort(scenes.begin(), scenes.end());
  return scenes;
}

FileWatch::FileWatch(std::filesystem::path file) : file_(std::move(file)) {
  loaded_ = seen_ = stamp();
}

std::optional<FileWatch::Stamp> FileWatch::stamp() const {
  std::error_code ec;
  const auto time = std::filesystem::last_write_time(file_, ec);
  if (ec) return std::nullopt;
  const auto size = std::filesystem::file_size(file_, ec);
  if (ec) return std::nullopt;
  return Stamp{time, size};
}

bool FileWatch::changed() {
  const auto now = stamp();
  const bool settled = now && now == seen_;
  seen_ = now;
  if (!settled || now == loaded_) return false;
  loaded_ = now;
  return true;
}

}  // namespace maille::viewer
