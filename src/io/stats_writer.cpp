#include <cerrno>
#include <cstring>
#include <stdexcept>

#include "maille/io.hpp"

namespace maille {

StatsWriter::StatsWriter(std::filesystem::path path) : file_(std::move(path)) {}

StatsWriter::StatsWriter(std::filesystem::path path, const std::vector<std::string>& kept)
    : file_(std::move(path)) {
  for (const auto& line : kept) file_.stream() << line << '\n';
  rows_ = kept.empty() ? 0 : kept.size() - 1;  // the first line is the header
  header_written_ = !kept.empty();
}

StatsWriter::~StatsWriter() {
  try {
    close();
  } catch (...) {  // a destructor must not throw; close() reports errors when called directly
  }
}

void StatsWriter::write(const EnergySample& sample, const Profile& profile) {
  auto& o = file_.stream();
  if (!header_written_) header(&profile);
  const char* separator = "";
  for_each_stats_column(sample, profile, [&](std::string_view, std::string_view, auto value) {
    o << separator << value;
    separator = ",";
  });
  o << '\n';
  if (!o.good())  // a full disk shows here when a buffer is flushed
    throw std::runtime_error("cannot write " + file_.path().string() + ": " +
                             (errno ? std::strerror(errno) : "write error"));
  ++rows_;
}

// With no profile (no sample was taken), the columns before the stages'.
void StatsWriter::header(const Profile* profile) {
  auto& o = file_.stream();
  const char* separator = "";
  for_each_stats_column(EnergySample{}, profile ? *profile : Profile{},
                        [&](std::string_view prefix, std::string_view name, auto) {
                          o << separator << prefix << name;
                          separator = ",";
                        });
  o << '\n';
  header_written_ = true;
}

void StatsWriter::close() {
  if (closed_) return;
  closed_ = true;
  if (!header_written_) header(nullptr);
  file_.commit();
}

void StatsWriter::close(const Profile& profile) {
  if (!closed_ && !header_written_) header(&profile);
  close();
}

}  // namespace maille
