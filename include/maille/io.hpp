// Output: frames (PLY, OBJ, legacy VTK) and statistics (CSV), each file written whole or not at
// all: bytes go to "<name>.tmp" and are renamed into place only when complete.
#pragma once

#include <cstdint>
#include <filesystem>
#include <fstream>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "maille/model.hpp"
#include "maille/names.hpp"
#include "maille/profile.hpp"
#include "maille/simulator.hpp"
#include "maille/smooth_surface.hpp"
#include "maille/snapshot.hpp"

namespace maille {

// Where the bytes of an output named `path` go. A regular file, or a name not taken yet, is
// replaced whole (through a temporary and a rename); a symbolic link is followed, so that the
// file it names is replaced and the link kept; a FIFO or a character device (a player reading
// a pipe, /dev/null, /dev/stdout) is written into directly, because a rename would replace the
// node itself (as root, /dev/null). Anything else (a directory, a socket, a block device, a
// dangling link) is refused: std::runtime_error naming the path and what it is.
struct OutputTarget {
  std::filesystem::path file;  // the file to replace or to write into
  bool direct = false;         // written in place (FIFO, character device): no temporary
};
OutputTarget output_target(const std::filesystem::path& path);

// A file that appears under its name only after commit(). Destroyed uncommitted, it leaves
// nothing behind. Throws std::runtime_error (naming the path and the cause: "No space left on
// device", "Permission denied") when it cannot open, write, flush, close or rename. A FIFO or a
// character device is written into directly (output_target): its reader sees the bytes as
// they come, and an interrupted write cannot be taken back.
class AtomicFile {
 public:
  explicit AtomicFile(std::filesystem::path path);
  ~AtomicFile();
  AtomicFile(const AtomicFile&) = delete;
  AtomicFile& operator=(const AtomicFile&) = delete;

  std::ofstream& stream() { return out_; }
  void commit();
  const std::filesystem::path& path() const { return path_; }

 private:
  std::filesystem::path path_, tmp_;  // tmp_ empty when written directly
  std::ofstream out_;
  bool committed_ = false;
};

enum class FrameFormat : std::uint8_t { ply, obj, vtk };
template <>
struct NameTable<FrameFormat> {
  static constexpr std::string_view what = "frame format";
  static constexpr std::array<Name<FrameFormat>, 3> names{{
      {FrameFormat::ply, "ply", "ASCII PLY: points and faces"},
      {FrameFormat::obj, "obj", "Wavefront OBJ: points, faces and links as lines"},
      {FrameFormat::vtk, "vtk", "legacy VTK polydata, with a fixed/free point scalar"},
  }};
};
inline std::optional<FrameFormat> parse_frame_format(std::string_view name) {
  return parse_name<FrameFormat>(name);
}
// The file extension is the format's name.
inline std::string_view extension(FrameFormat f) {
  return to_string(f);
}

// One frame: the points, the surface faces, and every link as a line (renderers colour them).
void write_frame(const std::filesystem::path& path, FrameFormat format, const Model& m,
                 const Snapshot& s);

// Writes dir/frame_000000.<ext>, dir/frame_000001.<ext>, ... as snapshots arrive.
class FrameWriter {
 public:
  // smooth_lod > 0 (OBJ only): each frame is the smooth surface through the particles
  // (smooth_surface.hpp) at that level of detail, with its normals, for Blender and the like.
  FrameWriter(std::filesystem::path dir, FrameFormat format, const Model& m, int smooth_lod = 0);
  void operator()(const Snapshot& s);
  std::uint64_t written() const { return written_; }

 private:
  std::filesystem::path dir_;
  FrameFormat format_;
  const Model& model_;
  std::uint64_t written_ = 0;
  int smooth_lod_ = 0;
  SmoothSurface smooth_;
  SmoothMesh smooth_mesh_;
};

// The smooth surface of a frame as an OBJ file: v, vn and f a//a lines.
void write_smooth_obj(const std::filesystem::path& path, const SmoothMesh& mesh, const Snapshot& s);

// stats.csv's columns, in order: time, step, the energies (for_each_energy), ns_<stage> (each
// stage's time during the step, ns), the counters, the gauges. The one list: StatsWriter writes
// it and the Python module's Simulation.stats() reads it. `column(prefix, name, value)` is
// called once per column, value a double, or a std::uint64_t for step and the counters (which
// are integers in the file).
template <class Column>
void for_each_stats_column(const EnergySample& e, const Profile& p, Column&& column) {
  column(std::string_view(), std::string_view("time"), e.time);
  column(std::string_view(), std::string_view("step"), e.step);
  for_each_energy(e.energies, [&](const char* name, double value) {
    column(std::string_view(), std::string_view(name), value);
  });
  for (const auto& s : p.stages())
    column(std::string_view("ns_"), std::string_view(s.name), s.last_ns);
  for (const auto& c : p.counters()) column(std::string_view(), std::string_view(c.name), c.last);
  for (const auto& g : p.gauges()) column(std::string_view(), std::string_view(g.name), g.last);
}

// stats.csv: one row per energy sample: time, step, energies, ns per stage during that step,
// counters. The header is written with the first row (stages plugged in before then appear),
// or by close() when no row was (a blow-up at step 1): the file always has its header.
// Rows are complete lines; the file is renamed into place by close() (or the destructor).
class StatsWriter {
 public:
  explicit StatsWriter(std::filesystem::path path);
  // Resuming: the file starts with `kept` (the header and the rows written before the
  // checkpoint, read from the previous stats.csv) and continues after them.
  StatsWriter(std::filesystem::path path, const std::vector<std::string>& kept);
  ~StatsWriter();
  StatsWriter(const StatsWriter&) = delete;
  StatsWriter& operator=(const StatsWriter&) = delete;

  // Throws std::runtime_error with the cause as soon as the stream reports a failed write.
  void write(const EnergySample& sample, const Profile& profile);
  void close();                        // with no row written, the header lists the energies
  void close(const Profile& profile);  // ... and the profile's columns
  std::uint64_t rows() const { return rows_; }

 private:
  void header(const Profile* profile);
  AtomicFile file_;
  std::uint64_t rows_ = 0;
  bool header_written_ = false;
  bool closed_ = false;
};

}  // namespace maille
