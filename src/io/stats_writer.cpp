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
  const Energies& e = sample.energies;
  o << sample.time << ',' << sample.step;
  for_each_energy(e, [&](const char*, double value) { o << ',' << value; });
  for (const auto& s : profile.stages()) o << ',' << s.last_ns;
  for (const auto& c : profile.counters()) o << ',' << c.last;
  for (const auto& g : profile.gauges()) o << ',' << g.last;
  o << '\n';
  if (!o.good())  // a full disk shows here when a buffer is flushed
    throw std::runtime_error("cannot write " + file_.path().string() + ": " +
                             (errno ? std::strerror(errno) : "write error"));
  ++rows_;
}

void StatsWriter::header(const Profile* profile) {
  auto& o = file_.stream();
  o << "time,step";
  for_each_energy(Energies{}, [&](const char* name, double) { o << ',' << name; });
  if (profile) {
    for (const auto& s : profile->stages()) o << ",ns_" << s.name;
    for (const auto& c : profile->counters()) o << ',' << c.name;
    for (const auto& g : profile->gauges()) o << ',' << g.name;
  }
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
