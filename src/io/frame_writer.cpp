#include <cstdio>
#include <stdexcept>
#include <vector>

#include "maille/io.hpp"

namespace maille {

namespace {

std::vector<LinkEnds> all_links(const Model& m) {
  std::vector<LinkEnds> out;
  out.reserve(m.links.total());
  for (const auto& pool : m.links.pools())
    for (std::size_t i = 0; i < pool->size(); ++i) out.push_back(pool->ends(i));
  return out;
}

void ply(std::ostream& o, const Model& m, const Snapshot& s) {
  const auto links = all_links(m);
  o << "ply\nformat ascii 1.0\ncomment maille frame " << s.frame << " step " << s.step << " time "
    << s.time << "\nelement vertex " << s.positions.size()
    << "\nproperty float x\nproperty float y\nproperty float z\nproperty uchar fixed\n"
    << "element face " << m.surface.triangles.size() << "\nproperty list uchar int vertex_indices\n"
    << "element edge " << links.size() << "\nproperty int vertex1\nproperty int vertex2\n"
    << "end_header\n";
  for (std::size_t i = 0; i < s.positions.size(); ++i) {
    const Vec3& p = s.positions[i];
    o << p.x << ' ' << p.y << ' ' << p.z << ' ' << (m.points.inv_mass[i] > 0 ? 0 : 1) << '\n';
  }
  for (const auto& t : m.surface.triangles) o << "3 " << t[0] << ' ' << t[1] << ' ' << t[2] << '\n';
  for (const auto& l : links) o << l.a << ' ' << l.b << '\n';
}

void obj(std::ostream& o, const Model& m, const Snapshot& s) {
  o << "# maille frame " << s.frame << " step " << s.step << " time " << s.time << '\n';
  for (const Vec3& p : s.positions) o << "v " << p.x << ' ' << p.y << ' ' << p.z << '\n';
  for (const auto& t : m.surface.triangles)  // OBJ indices are 1-based
    o << "f " << t[0] + 1 << ' ' << t[1] + 1 << ' ' << t[2] + 1 << '\n';
  for (const auto& l : all_links(m)) o << "l " << l.a + 1 << ' ' << l.b + 1 << '\n';
}

void vtk(std::ostream& o, const Model& m, const Snapshot& s) {
  const auto links = all_links(m);
  const std::size_t tris = m.surface.triangles.size();
  o << "# vtk DataFile Version 3.0\nmaille frame " << s.frame << " step " << s.step << " time "
    << s.time << "\nASCII\nDATASET POLYDATA\nPOINTS " << s.positions.size() << " double\n";
  for (const Vec3& p : s.positions) o << p.x << ' ' << p.y << ' ' << p.z << '\n';
  if (!links.empty()) {
    o << "LINES " << links.size() << ' ' << links.size() * 3 << '\n';
    for (const auto& l : links) o << "2 " << l.a << ' ' << l.b << '\n';
  }
  if (tris) {
    o << "POLYGONS " << tris << ' ' << tris * 4 << '\n';
    for (const auto& t : m.surface.triangles)
      o << "3 " << t[0] << ' ' << t[1] << ' ' << t[2] << '\n';
  }
  o << "POINT_DATA " << s.positions.size() << "\nSCALARS fixed int 1\nLOOKUP_TABLE default\n";
  for (std::size_t i = 0; i < s.positions.size(); ++i)
    o << (m.points.inv_mass[i] > 0 ? 0 : 1) << '\n';
}

}  // namespace

void write_frame(const std::filesystem::path& path, FrameFormat format, const Model& m,
                 const Snapshot& s) {
  AtomicFile file(path);
  switch (format) {
    case FrameFormat::ply:
      ply(file.stream(), m, s);
      break;
    case FrameFormat::obj:
      obj(file.stream(), m, s);
      break;
    case FrameFormat::vtk:
      vtk(file.stream(), m, s);
      break;
  }
  file.commit();
}

FrameWriter::FrameWriter(std::filesystem::path dir, FrameFormat format, const Model& m,
                         int smooth_lod)
    : dir_(std::move(dir)), format_(format), model_(m), smooth_lod_(smooth_lod) {
  if (smooth_lod_ > 0) {
    if (format_ != FrameFormat::obj)
      throw std::invalid_argument("smooth frames are written as OBJ only");
    smooth_ = SmoothSurface(m);
    if (smooth_.empty()) throw std::invalid_argument("the scene has no surface to smooth");
  }
}

void write_smooth_obj(const std::filesystem::path& path, const SmoothMesh& mesh,
                      const Snapshot& s) {
  AtomicFile file(path);
  std::ostream& o = file.stream();
  o << "# maille frame " << s.frame << " step " << s.step << " time " << s.time
    << " (smooth surface)\n";
  const std::vector<float>& v = mesh.vertices;
  for (std::size_t i = 0; i + 5 < v.size(); i += 6)
    o << "v " << v[i] << ' ' << v[i + 1] << ' ' << v[i + 2] << '\n';
  for (std::size_t i = 0; i + 5 < v.size(); i += 6)
    o << "vn " << v[i + 3] << ' ' << v[i + 4] << ' ' << v[i + 5] << '\n';
  const std::vector<std::uint32_t>& t = mesh.triangles;
  for (std::size_t i = 0; i + 2 < t.size(); i += 3)  // OBJ indices are 1-based
    o << "f " << t[i] + 1 << "//" << t[i] + 1 << ' ' << t[i + 1] + 1 << "//" << t[i + 1] + 1 << ' '
      << t[i + 2] + 1 << "//" << t[i + 2] + 1 << '\n';
  file.commit();
}

void FrameWriter::operator()(const Snapshot& s) {
  char name[64];
  std::snprintf(name, sizeof name, "frame_%06llu.%s", static_cast<unsigned long long>(s.frame),
                extension(format_).data());
  if (smooth_lod_ > 0) {
    smooth_.evaluate(s.positions, smooth_lod_, smooth_mesh_);
    write_smooth_obj(dir_ / name, smooth_mesh_, s);
  } else {
    write_frame(dir_ / name, format_, model_, s);
  }
  ++written_;
}

}  // namespace maille
