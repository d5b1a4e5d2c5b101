// Frames and statistics: the formats parse back, and files appear whole or not at all.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>

#include "maille/builders.hpp"
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

Model small_flag() {
  Model m;
  FlagParams p;
  p.nx = 4;
  p.ny = 3;
  build_flag(m, p, "flag");
  return m;
}

Snapshot snapshot_of(const Model& m) {
  Snapshot s;
  s.frame = 7;
  s.positions = m.points.initial_position;
  return s;
}

TEST(Io, PlyHasCountsInHeaderAndBody) {
  const Model m = small_flag();
  const auto dir = temp_dir("ply");
  write_frame(dir / "f.ply", FrameFormat::ply, m, snapshot_of(m));
  const std::string text = slurp(dir / "f.ply");
  EXPECT_NE(text.find("element vertex 12\n"), std::string::npos);
  EXPECT_NE(text.find("element face 12\n"), std::string::npos);  // 3x2 cells, 2 faces each
  std::istringstream lines(text.substr(text.find("end_header\n") + 11));
  std::string line;
  int count = 0;
  while (std::getline(lines, line)) ++count;
  EXPECT_EQ(count, 12 + 12 + static_cast<int>(m.links.total()));
}

TEST(Io, ObjIndicesAreOneBased) {
  const Model m = small_flag();
  const auto dir = temp_dir("obj");
  write_frame(dir / "f.obj", FrameFormat::obj, m, snapshot_of(m));
  const std::string text = slurp(dir / "f.obj");
  EXPECT_NE(text.find("\nf 1 2 6\n"), std::string::npos);
  EXPECT_EQ(text.find("\nf 0"), std::string::npos);
}

TEST(Io, VtkDeclaresPointsLinesPolygons) {
  const Model m = small_flag();
  const auto dir = temp_dir("vtk");
  write_frame(dir / "f.vtk", FrameFormat::vtk, m, snapshot_of(m));
  const std::string text = slurp(dir / "f.vtk");
  EXPECT_NE(text.find("POINTS 12 double"), std::string::npos);
  EXPECT_NE(text.find("POLYGONS 12 48"), std::string::npos);
  EXPECT_NE(text.find("LINES " + std::to_string(m.links.total())), std::string::npos);
}

// An AtomicFile destroyed before commit leaves neither the file nor its temporary.
TEST(Io, UncommittedFileLeavesNothing) {
  const auto dir = temp_dir("atomic");
  {
    AtomicFile f(dir / "out.csv");
    f.stream() << "half a result";
  }
  EXPECT_FALSE(std::filesystem::exists(dir / "out.csv"));
  EXPECT_FALSE(std::filesystem::exists(dir / "out.csv.tmp"));
  {
    AtomicFile f(dir / "out.csv");
    f.stream() << "whole";
    EXPECT_FALSE(std::filesystem::exists(dir / "out.csv"));  // not visible until committed
    f.commit();
  }
  EXPECT_EQ(slurp(dir / "out.csv"), "whole");
}

TEST(Io, UnwritableDirectoryIsAClearError) {
  EXPECT_THROW(AtomicFile("/nonexistent_dir/x.csv"), std::runtime_error);
}

TEST(Io, StatsCsvHasHeaderAndOneRowPerSample) {
  const auto dir = temp_dir("stats");
  Model m = small_flag();
  SimulationSettings s;
  s.step = 1e-4;
  s.sample_every = 10;
  Simulator sim(std::move(m), s);
  {
    StatsWriter stats(dir / "stats.csv");
    sim.on_sample([&](const EnergySample& e, const Profile& p) { stats.write(e, p); });
    sim.run_steps(100);
    EXPECT_FALSE(std::filesystem::exists(dir / "stats.csv"));
    stats.close();
  }
  std::istringstream in(slurp(dir / "stats.csv"));
  std::string header, row;
  std::getline(in, header);
  EXPECT_EQ(header.rfind("time,step,kinetic,elastic,gravity,contact,total,ns_drive", 0), 0u) << header;
  int rows = 0;
  while (std::getline(in, row)) ++rows;
  EXPECT_EQ(rows, 10);
}

}  // namespace
}  // namespace maille
