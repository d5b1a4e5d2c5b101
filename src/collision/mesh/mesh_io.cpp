// Mesh files: reading one (refusing what is not a readable regular file, then telling the
// format by content) and writing a mesh as OBJ.
#include <cerrno>
#include <charconv>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>

#include "mesh_checks.hpp"

namespace maille {

namespace {

using mesh_detail::fail;

// The whole file, at most mesh_limits::max_file_bytes: a directory, a device or a FIFO is
// refused before reading, since /dev/zero or a pipe would be read without end.
std::string read_bytes(const std::string& path) {
  namespace fs = std::filesystem;
  // The system would read the path up to the NUL: another file than the one named.
  if (path.find('\0') != std::string::npos)
    fail(path.substr(0, path.find('\0')) + "\\0...", 0, "the path contains a NUL byte");
  std::error_code ec;
  const fs::file_status status = fs::status(path, ec);
  if (ec || !fs::exists(status))
    fail(path, 0,
         "cannot open the mesh file: " +
             (ec ? ec.message() : std::string("no such file or directory")));
  if (fs::is_directory(status)) fail(path, 0, "is a directory, not a mesh file");
  if (!fs::is_regular_file(status)) fail(path, 0, "is not a regular file (a device or a pipe?)");
  const std::uintmax_t size = fs::file_size(path, ec);
  if (ec) fail(path, 0, "cannot read the mesh file: " + ec.message());
  if (size > mesh_limits::max_file_bytes)
    fail(path, 0,
         "is " + std::to_string(size) + " bytes; mesh files are limited to " +
             std::to_string(mesh_limits::max_file_bytes) + " bytes (1 GiB)");
  std::ifstream in(path, std::ios::binary);
  if (!in) fail(path, 0, std::string("cannot open the mesh file: ") + std::strerror(errno));
  // Only the measured size is read (the file may grow meanwhile: the limit holds).
  std::string bytes(static_cast<std::size_t>(size), '\0');
  in.read(bytes.data(), static_cast<std::streamsize>(bytes.size()));
  bytes.resize(static_cast<std::size_t>(in.gcount()));
  if (in.bad()) fail(path, 0, std::string("cannot read the mesh file: ") + std::strerror(errno));
  return bytes;
}

}  // namespace

// Content, not extension, decides: a binary STL is recognised by its exact size (84 + 50 n),
// an ASCII one by "solid" and a facet or endsolid; text with a NUL byte is no OBJ, so it goes
// to the STL reader too (a binary STL cut short says "truncated" there); the rest is OBJ.
TriMesh read_mesh(const std::string& path) {
  const std::string bytes = read_bytes(path);
  if (bytes.empty()) fail(path, 0, "empty file");
  if (mesh_detail::looks_like_binary_stl(bytes) || mesh_detail::looks_like_ascii_stl(bytes) ||
      bytes.find('\0') != std::string::npos)
    return parse_stl(bytes, path);
  return parse_obj(bytes, path);
}

// Shortest round-trip decimal (std::to_chars): parse_obj reads back the same doubles.
std::string to_obj(const TriMesh& mesh) {
  std::string out = "# maille TriMesh: " + std::to_string(mesh.vertices.size()) + " vertices, " +
                    std::to_string(mesh.triangles.size()) + " triangles\n";
  out.reserve(out.size() + 48 * mesh.vertices.size() + 24 * mesh.triangles.size());
  char buf[64];
  auto put = [&](auto value) {
    const auto r = std::to_chars(buf, buf + sizeof buf, value);
    out.append(buf, r.ptr);
  };
  for (const Vec3& v : mesh.vertices) {
    out += 'v';
    for (const Real c : {v.x, v.y, v.z}) out += ' ', put(c);
    out += '\n';
  }
  for (const auto& t : mesh.triangles) {
    out += 'f';
    for (const std::uint32_t i : t) out += ' ', put(std::uint64_t{i} + 1);
    out += '\n';
  }
  return out;
}

}  // namespace maille
