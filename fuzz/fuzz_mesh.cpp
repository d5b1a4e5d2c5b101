// libFuzzer target: arbitrary bytes -> parse_obj and parse_stl. A bad file must come back as a
// MeshError; anything else (a crash, a sanitizer report, another exception, a timeout, memory
// beyond the limit) is a bug. What is accepted must also be what the readers promise: at least
// one triangle, indices in range, finite coordinates, no zero-area face, and to_obj ->
// parse_obj gives the same mesh back, bit for bit.
// Build: cmake --preset fuzz && cmake --build --preset fuzz; run: scripts/fuzz.sh [--quick].
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <string>
#include <string_view>

#include "maille/mesh.hpp"

namespace {

using Parser = maille::TriMesh (*)(std::string_view, const std::string&);

void require(bool ok, const char* what) {
  if (ok) return;
  std::fprintf(stderr, "fuzz_mesh: accepted mesh breaks a promise: %s\n", what);
  __builtin_trap();
}

void check(Parser parse, std::string_view bytes, const char* name) {
  maille::TriMesh mesh;
  try {
    mesh = parse(bytes, name);
  } catch (const maille::MeshError&) {
    return;
  }
  require(!mesh.triangles.empty(), "no triangles");
  for (const auto& t : mesh.triangles)
    for (const auto i : t) require(i < mesh.vertices.size(), "index out of range");
  for (const maille::Vec3& v : mesh.vertices) require(maille::is_finite(v), "non-finite vertex");
  // The measures run on anything accepted (their result is not judged: an open mesh's volume
  // means nothing).
  (void)mesh.closed();
  (void)mesh.volume();
  (void)mesh.area();
  maille::TriMesh back;
  try {
    back = maille::parse_obj(maille::to_obj(mesh), "round_trip.obj");
  } catch (const maille::MeshError& e) {
    std::fprintf(stderr, "fuzz_mesh: to_obj output refused: %s\n", e.what());
    __builtin_trap();
  }
  require(back.vertices == mesh.vertices, "round trip changed the vertices");
  require(back.triangles == mesh.triangles, "round trip changed the triangles");
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string_view bytes(reinterpret_cast<const char*>(data), size);
  check(maille::parse_obj, bytes, "fuzz.obj");
  check(maille::parse_stl, bytes, "fuzz.stl");
  return 0;
}
