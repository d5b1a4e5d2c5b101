#include <cerrno>
#include <cstring>
#include <stdexcept>
#include <system_error>

#include "maille/io.hpp"

namespace maille {

namespace {

// The cause of the last failed system call, for messages ("No space left on device").
std::string cause(int err) {
  return err ? std::string(std::strerror(err)) : std::string("write error");
}

}  // namespace

AtomicFile::AtomicFile(std::filesystem::path path)
    : path_(std::move(path)), tmp_(path_.string() + ".tmp") {
  errno = 0;
  out_.open(tmp_, std::ios::binary | std::ios::trunc);
  if (!out_) throw std::runtime_error("cannot write " + tmp_.string() + ": " + cause(errno));
  out_.precision(9);
}

AtomicFile::~AtomicFile() {
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
    std::filesystem::remove(tmp_, ignored);
    committed_ = true;  // nothing left to clean up
    throw std::runtime_error("cannot write " + path_.string() + ": " + cause(err));
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

}  // namespace maille
