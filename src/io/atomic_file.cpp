#include <stdexcept>
#include <system_error>

#include "maille/io.hpp"

namespace maille {

AtomicFile::AtomicFile(std::filesystem::path path)
    : path_(std::move(path)), tmp_(path_.string() + ".tmp") {
  out_.open(tmp_, std::ios::binary | std::ios::trunc);
  if (!out_) throw std::runtime_error("cannot write " + tmp_.string());
  out_.precision(9);
}

AtomicFile::~AtomicFile() {
  if (committed_) return;
  out_.close();
  std::error_code ec;
  std::filesystem::remove(tmp_, ec);  // nothing half-written is left behind
}

void AtomicFile::commit() {
  out_.flush();
  const bool good = out_.good();
  out_.close();
  if (!good) throw std::runtime_error("error while writing " + tmp_.string());
  std::error_code ec;
  std::filesystem::rename(tmp_, path_, ec);
  if (ec) throw std::runtime_error("cannot rename " + tmp_.string() + ": " + ec.message());
  committed_ = true;
}

}  // namespace maille
