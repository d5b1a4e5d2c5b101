#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <cstring>
#include <stdexcept>
#include <system_error>

#include "maille/io.hpp"
#include "maille/temporary_files.hpp"

namespace maille {

namespace {

// The open temporaries, for remove_open_temporaries: a slot is claimed (1), its path written,
// then published (2); the handler reads published slots only. Paths longer than a slot, or
// more files open at once than slots, go unlisted (their temporaries would stay behind).
struct Slot {
  std::atomic<int> state{0};  // 0 free, 1 being written, 2 listed
  char path[4096];
};
Slot g_open[64];

void list_temporary(const std::string& path) {
  if (path.size() >= sizeof g_open[0].path) return;
  for (Slot& s : g_open) {
    int free = 0;
    if (!s.state.compare_exchange_strong(free, 1)) continue;
    std::memcpy(s.path, path.c_str(), path.size() + 1);
    s.state.store(2);
    return;
  }
}

void unlist_temporary(const std::string& path) {
  for (Slot& s : g_open)
    if (s.state.load() == 2 && path == s.path) {
      s.state.store(0);
      return;
    }
}

// The cause of the last failed system call, for messages ("No space left on device").
std::string cause(int err) {
  return err ? std::string(std::strerror(err)) : std::string("write error");
}

}  // namespace

OutputTarget output_target(const std::filesystem::path& path) {
  namespace fs = std::filesystem;
  std::error_code ec;
  const fs::file_status link = fs::symlink_status(path, ec);
  if (ec || !fs::exists(link)) return {path, false};  // a new file (or one open() will refuse)
  const fs::file_status st = fs::status(path, ec);
  if (ec || !fs::exists(st)) {
    if (fs::is_symlink(link))
      throw std::runtime_error("cannot write " + path.string() +
                               ": it is a symbolic link to nothing (name its target instead)");
    return {path, false};
  }
  fs::path file = path;
  if (fs::is_symlink(link)) {
    file = fs::canonical(path, ec);
    if (ec) throw std::runtime_error("cannot write " + path.string() + ": " + ec.message());
  }
  switch (st.type()) {
    case fs::file_type::regular:
      return {file, false};
    case fs::file_type::fifo:
    case fs::file_type::character:
      return {file, true};
    case fs::file_type::directory:
      throw std::runtime_error("cannot write " + path.string() + ": it is a directory");
    default:
      throw std::runtime_error("cannot write " + path.string() +
                               ": it is neither a regular file, a FIFO nor a character device");
  }
}

AtomicFile::AtomicFile(std::filesystem::path path) : path_(std::move(path)) {
  const OutputTarget target = output_target(path_);
  errno = 0;
  if (target.direct) {
    committed_ = false;
    out_.open(target.file, std::ios::binary | std::ios::out);
    if (!out_) throw std::runtime_error("cannot write " + path_.string() + ": " + cause(errno));
    out_.precision(9);
    return;
  }
  path_ = target.file;
  tmp_ = path_.string() + ".tmp";
  list_temporary(tmp_.string());
  out_.open(tmp_, std::ios::binary | std::ios::trunc);
  if (!out_) {
    unlist_temporary(tmp_.string());
    throw std::runtime_error("cannot write " + tmp_.string() + ": " + cause(errno));
  }
  out_.precision(9);
}

AtomicFile::~AtomicFile() {
  if (tmp_.empty()) return;  // written directly: nothing to take back
  unlist_temporary(tmp_.string());
  if (committed_) return;
  out_.close();
  std::error_code ec;
  std::filesystem::remove(tmp_, ec);  // nothing half-written is left behind
}

// Every step is checked: a write that failed earlier (the stream's state), the flush of the last
// buffer, and the close (where some file systems report a full disk). On failure the temporary
// is removed and the file under its name, if any, is left as it was.
void AtomicFile::commit() {
  int err = 0;
  bool good = out_.good();
  if (!good) err = errno;
  if (good) {
    errno = 0;
    out_.flush();
    if (!out_.good()) good = false, err = errno;
  }
  errno = 0;
  out_.close();
  if (good && out_.fail()) good = false, err = errno;
  if (!good) {
    std::error_code ignored;
    if (!tmp_.empty()) std::filesystem::remove(tmp_, ignored);
    committed_ = true;  // nothing left to clean up
    throw std::runtime_error("cannot write " + path_.string() + ": " + cause(err));
  }
  if (tmp_.empty()) {  // a FIFO or a device: written in place
    committed_ = true;
    return;
  }
  std::error_code ec;
  std::filesystem::rename(tmp_, path_, ec);
  if (ec) {
    std::error_code ignored;
    std::filesystem::remove(tmp_, ignored);
    committed_ = true;
    throw std::runtime_error("cannot rename " + tmp_.string() + " to " + path_.string() + ": " +
                             ec.message());
  }
  committed_ = true;
}

void remove_open_temporaries() noexcept {
  for (Slot& s : g_open)
    if (s.state.load() == 2) ::unlink(s.path);
}

}  // namespace maille
