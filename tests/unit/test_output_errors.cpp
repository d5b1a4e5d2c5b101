// Output errors: a full disk (/dev/full behind the temporary's name) or a missing directory is
// reported with its cause, nothing half-written is left, and what was there before survives.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>

#include "maille/io.hpp"

namespace maille {
namespace {

std::filesystem::path temp_dir(const std::string& name) {
  auto d = std::filesystem::temp_directory_path() / ("maille_test_" + name);
  std::filesystem::remove_all(d);
  std::filesystem::create_directories(d);
  return d;
}

std::string slurp(const std::filesystem::path& p) {
  std::ifstream in(p);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

// The temporary "<name>.tmp" is opened through a link to /dev/full: every write fails ENOSPC.
std::filesystem::path full_disk_file(const std::string& test) {
  const auto dir = temp_dir(test);
  const auto file = dir / "out.txt";
  std::ofstream(file) << "previous\n";
  std::filesystem::create_symlink("/dev/full", dir / "out.txt.tmp");
  return file;
}

TEST(OutputErrors, FullDiskNamesTheCauseAndKeepsThePreviousFile) {
  const auto file = full_disk_file("full_disk");
  AtomicFile f(file);
  f.stream() << std::string(1 << 20, 'x');  // more than a buffer: a write fails here already
  try {
    f.commit();
    FAIL() << "commit succeeded on a full disk";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("No space left on device"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find(file.string()), std::string::npos) << e.what();
  }
  EXPECT_EQ(slurp(file), "previous\n");
  EXPECT_FALSE(std::filesystem::exists(std::filesystem::symlink_status(file.string() + ".tmp")));
}

TEST(OutputErrors, FullDiskOnTheLastSmallWriteIsCaughtAtCommit) {
  const auto file = full_disk_file("full_disk_small");
  AtomicFile f(file);
  f.stream() << "a few bytes, still in the buffer";
  EXPECT_THROW(f.commit(), std::runtime_error);
  EXPECT_EQ(slurp(file), "previous\n");
}

TEST(OutputErrors, MissingDirectoryNamesTheCause) {
  try {
    AtomicFile f("/nonexistent_maille_dir/out.txt");
    FAIL() << "opened a file in a missing directory";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("No such file or directory"), std::string::npos)
        << e.what();
  }
}

TEST(OutputErrors, StatsWithoutARowStillHasItsHeader) {
  const auto dir = temp_dir("stats_header");
  {
    StatsWriter stats(dir / "stats.csv");
    stats.close();
  }
  EXPECT_EQ(slurp(dir / "stats.csv"), "time,step,kinetic,elastic,gravity,contact,total\n");
  {
    Profile profile;
    StatsWriter stats(dir / "stats2.csv");
    stats.close(profile);
    stats.close(profile);  // idempotent: one header
  }
  EXPECT_EQ(slurp(dir / "stats2.csv").rfind("time,step,kinetic", 0), 0u);
  EXPECT_EQ(slurp(dir / "stats2.csv").find("time", 1), std::string::npos);
}

}  // namespace
}  // namespace maille
