// Mesh files: OBJ and STL (ASCII and binary) round trips keep the triangles, welding makes
// STL surfaces closed, and every malformed file is a MeshError naming the file and the
// problem (tests/data/meshes/bad, and in-memory variants of each check).
#include <gtest/gtest.h>

#include <cstring>
#include <string>
#include <vector>

#include "maille/mesh.hpp"

namespace maille {
namespace {

const std::string kData = std::string(MAILLE_TEST_DATA) + "/meshes/";

// The message of the MeshError that f throws; a failure if it throws nothing (or another type).
template <class F>
std::string error_of(F&& f) {
  try {
    f();
  } catch (const MeshError& e) {
    return e.what();
  }
  ADD_FAILURE() << "no MeshError";
  return {};
}

std::string ascii_stl(const TriMesh& m) {
  std::string s = "solid test\n";
  for (const auto& t : m.triangles) {
    s += "facet normal 0 0 0\nouter loop\n";
    for (const auto i : t) {
      const Vec3 v = m.vertices[i];
      char buf[128];
      std::snprintf(buf, sizeof buf, "vertex %.17g %.17g %.17g\n", double(v.x), double(v.y),
                    double(v.z));
      s += buf;
    }
    s += "endloop\nendfacet\n";
  }
  return s + "endsolid test\n";
}

std::string binary_stl(const TriMesh& m) {
  std::string s(80, ' ');
  const auto n = static_cast<std::uint32_t>(m.triangles.size());
  for (int k = 0; k < 4; ++k) s += static_cast<char>((n >> (8 * k)) & 0xff);
  auto put = [&s](float f) {
    std::uint32_t bits;
    std::memcpy(&bits, &f, 4);
    for (int k = 0; k < 4; ++k) s += static_cast<char>((bits >> (8 * k)) & 0xff);
  };
  for (const auto& t : m.triangles) {
    for (int k = 0; k < 3; ++k) put(0);
    for (const auto i : t)
      put(float(m.vertices[i].x)), put(float(m.vertices[i].y)), put(float(m.vertices[i].z));
    s += std::string(2, '\0');
  }
  return s;
}

// The same triangles, corner by corner, up to the vertices' numbering (STL welding numbers
// them in order of first use).
void expect_same_triangles(const TriMesh& a, const TriMesh& b, double tol) {
  ASSERT_EQ(a.triangles.size(), b.triangles.size());
  for (std::size_t t = 0; t < a.triangles.size(); ++t)
    for (int k = 0; k < 3; ++k) {
      const Vec3 p = a.vertices[a.triangles[t][k]], q = b.vertices[b.triangles[t][k]];
      ASSERT_NEAR(double(p.x), double(q.x), tol);
      ASSERT_NEAR(double(p.y), double(q.y), tol);
      ASSERT_NEAR(double(p.z), double(q.z), tol);
    }
}

TEST(mesh_io, ObjRoundTripIsExact) {
  const TriMesh m = tessellate(shape_kind("torus"), 24, Real(0.35));
  const TriMesh back = parse_obj(to_obj(m), "torus.obj");
  EXPECT_EQ(back.vertices, m.vertices);  // shortest round-trip decimals, read exactly
  EXPECT_EQ(back.triangles, m.triangles);
  EXPECT_TRUE(back.closed());
}

TEST(mesh_io, StlRoundTripsWeldIntoTheSameSurface) {
  const TriMesh m = tessellate(shape_kind("capsule"), 16);
  const TriMesh a = parse_stl(ascii_stl(m), "capsule.stl");
  expect_same_triangles(m, a, 0);
  EXPECT_EQ(a.vertices.size(), m.vertices.size());  // welded back to shared corners
  EXPECT_TRUE(a.closed());
  const TriMesh b = parse_stl(binary_stl(m), "capsule_binary.stl");
  expect_same_triangles(m, b, 1e-7);  // float
  EXPECT_EQ(b.vertices.size(), m.vertices.size());
  EXPECT_TRUE(b.closed());
  EXPECT_NEAR(double(b.volume()), double(m.volume()), 1e-5);
}

TEST(mesh_io, ExampleFilesRead) {
  const TriMesh cube = read_mesh(kData + "cube_quads.obj");  // quads, groups, normals, usemtl
  EXPECT_EQ(cube.triangles.size(), 12u);
  EXPECT_TRUE(cube.closed());
  EXPECT_NEAR(double(cube.volume()), 8, 1e-14);
  EXPECT_NEAR(double(cube.area()), 24, 1e-14);
  for (const char* file : {"tetra.obj", "tetra_ascii.stl", "tetra_binary.stl"}) {
    SCOPED_TRACE(file);
    const TriMesh t = read_mesh(kData + file);
    EXPECT_EQ(t.vertices.size(), 4u);
    EXPECT_EQ(t.triangles.size(), 4u);
    EXPECT_TRUE(t.closed());
    EXPECT_NEAR(double(t.volume()), 1.0 / 6, 1e-15);
  }
}

// The committed example models (scripts/make_example_meshes.py) are usable obstacles.
TEST(mesh_io, ExampleModelsAreClosedAndOutward) {
  const std::string models = std::string(MAILLE_SOURCE_DIR) + "/examples/models/";
  const TriMesh rock = read_mesh(models + "rock.obj");
  EXPECT_EQ(rock.triangles.size(), 5120u);  // icosphere level 4
  EXPECT_TRUE(rock.closed());
  EXPECT_GT(rock.volume(), 0);
  for (const Vec3& p : rock.vertices) {
    EXPECT_GT(double(norm(p)), 0.7);
    EXPECT_LT(double(norm(p)), 1.2);
  }
  const TriMesh chair = read_mesh(models + "armchair.obj");
  EXPECT_EQ(chair.triangles.size(), 8u * 12);  // eight boxes
  EXPECT_TRUE(chair.closed());
  EXPECT_GT(chair.volume(), 0);
  // The bowl: half a shell between radii 0.9 and 1, (2 pi / 3)(1 - 0.9^3) = 0.5676 m^3 for
  // the smooth one; its polyhedron is inscribed: within 3 theta^2 / 8 per curved direction
  // (test_mesh.cpp), theta = 2 pi / 48 around and (pi / 2) / 8 along: 2.1 %.
  const TriMesh bowl = read_mesh(models + "bowl.obj");
  EXPECT_TRUE(bowl.closed());
  const double around = 2 * 3.14159265358979 / 48, along = 3.14159265358979 / 16;
  const double bound = 3 * (around * around + along * along) / 8;
  EXPECT_NEAR(double(bowl.volume()), 2 * 3.14159265358979 / 3 * (1 - 0.729), bound * 0.5676);
}

// Each file in tests/data/meshes/bad: the message starts with the file's path (and its line
// where one is known) and says what is wrong.
// A path that is not a mesh (a scene's `mesh` climbing out with ../ to a system file) is
// refused without its contents in the message; a NUL in a path is refused, not cut short.
TEST(mesh_io, ErrorsNeverQuoteAFileThatIsNoMesh) {
  const std::string secret = "root:x:0:0:root:/root:/bin/bash\ndaemon:x:1:1\n";
  const std::string message = error_of([&] { parse_obj(secret, "passwd"); });
  EXPECT_NE(message.find("passwd:1: not a mesh file"), std::string::npos) << message;
  EXPECT_EQ(message.find("root"), std::string::npos) << message;
  const std::string nul = error_of([] { read_mesh(std::string("/etc/passwd\0.obj", 16)); });
  EXPECT_NE(nul.find("the path contains a NUL byte"), std::string::npos) << nul;
  EXPECT_EQ(nul.find("root"), std::string::npos) << nul;
}

TEST(mesh_io, BadFilesSayWhatAndWhere) {
  const struct {
    const char* file;
    const char* phrase;
  } bad[] = {
      {"truncated_binary.stl", ": truncated: the header says 2 triangles (184 bytes)"},
      {"truncated_ascii.stl", ":12: truncated: the file ends where a number was expected"},
      {"nan_coordinate.obj", ":3: NaN or infinite coordinate (vertex 3)"},
      {"nan_coordinate.stl", ":5: NaN or infinite coordinate in facet 1"},
      {"zero_area_face.obj", ":7: zero-area face 2"},
      {"index_out_of_range.obj", ":4: vertex index out of range: '4' (3 defined so far)"},
      {"not_a_number.obj", ":3: not a number: '1.5x'"},
      {"unknown_statement.obj", ":4: unknown statement 'curv'"},
      {"too_many_triangles.stl", ": too many triangles: the header says 20000000"},
      {"empty.obj", ": empty file"},
      {"directory.obj", ": is a directory"},
  };
  for (const auto& b : bad) {
    SCOPED_TRACE(b.file);
    const std::string path = kData + "bad/" + b.file;
    const std::string message = error_of([&] { read_mesh(path); });
    EXPECT_EQ(message.rfind(path, 0), 0u) << message;
    EXPECT_NE(message.find(b.phrase), std::string::npos) << message;
  }
  const std::string missing = error_of([] { read_mesh(kData + "no_such_file.obj"); });
  EXPECT_NE(missing.find("such file or directory"), std::string::npos) << missing;
  const std::string device = error_of([] { read_mesh("/dev/zero"); });
  EXPECT_NE(device.find("/dev/zero: is not a regular file"), std::string::npos) << device;
}

// Every check of the OBJ scan, in memory: "NAME:LINE: " then the phrase.
TEST(mesh_io, MalformedObjIsRefused) {
  const std::string tri = "v 0 0 0\nv 1 0 0\nv 0 1 0\n";
  const struct {
    std::string text, phrase;
  } bad[] = {
      {"v 1 2\nf 1 2 3\n", "m.obj:1: a vertex has 3, 4 (x y z w) or 6 (x y z r g b) numbers"},
      {"v 1 2 3 4 5\n", "m.obj:1: a vertex has 3"},
      {"v 1e400 0 0\n", "m.obj:1: number out of the range of a double: '1e400'"},
      {"v 1e16 0 0\n", "m.obj:1: coordinate beyond 1e+15 (vertex 1)"},
      {"v -inf 0 0\n", "m.obj:1: NaN or infinite coordinate (vertex 1)"},
      {"v 0x10 0 0\n", "m.obj:1: not a number: '0x10'"},
      {"v 1.5e 0 0\n", "m.obj:1: not a number"},
      {"v 0 0 0 nan 0 0\n", "m.obj:1: NaN or infinite value (vertex 1)"},
      {"vn 0 1\n", "m.obj:1: 'vn' takes 3 numbers, found 2"},
      {"vt abc\n", "m.obj:1: not a number: 'abc'"},
      {tri + "f 1 2 3 4\n", "m.obj:4: vertex index out of range: '4' (3 defined so far)"},
      {tri + "f 0 1 2\n", "m.obj:4: vertex index out of range: 0 (OBJ indices start at 1)"},
      {tri + "f -4 1 2\n", "m.obj:4: vertex index out of range: '-4' (3 defined before it)"},
      {tri + "f 1 2 99999999999999999999999\n", "m.obj:4: vertex index out of range"},
      {tri + "f 1 2 3a\n", "m.obj:4: not a number: '3a' (a vertex index)"},
      {tri + "f 1/1 2 3\n", "m.obj:4: texture coordinate index out of range"},
      {tri + "f 1//1 2 3\n", "m.obj:4: normal index out of range"},
      {tri + "f 1/ 2 3\n", "m.obj:4: bad vertex reference '1/'"},
      {tri + "f 1/1/1/1 2 3\n", "m.obj:4: bad vertex reference"},
      {tri + "f 1 2\n", "m.obj:4: a face needs at least 3 vertices, found 2"},
      {tri + "l 1\n", "m.obj:4: a line needs at least 2 vertices"},
      {tri + "f 1 1 2\n", "m.obj:4: zero-area face 1"},
      {tri + "f 1 2 3\nf 1 2 3\nf 1 3 2 2\n", "m.obj:6: zero-area face 3"},
      {tri + "s 99999999999\nf 1 2 3\n", "m.obj:4: bad smoothing group"},
      {tri + "vw 1 2 3\n", "m.obj:4: unknown statement 'vw'"},
      {tri + "abcdefghijklmnopqrstuvwxyz\n", "m.obj:4: unknown statement 'abcdefghijklmnop...'"},
      {"root:x:0:0:root:/root:/bin/bash\n",
       "m.obj:1: not a mesh file: its first statement is none"},
      {tri + "f 1 2 3\n\x01\x02\n", "m.obj:5: unknown statement '\\x01\\x02'"},
      {tri + std::string("f 1 2\0 3\n", 9), "m.obj:4: NUL byte"},
      {"# nothing\n\n", "m.obj: empty mesh (no triangles)"},
      {tri, "m.obj: empty mesh (no triangles)"},
      {"", "m.obj: empty file"},
  };
  for (const auto& b : bad) {
    SCOPED_TRACE(b.text);
    const std::string message = error_of([&] { parse_obj(b.text, "m.obj"); });
    EXPECT_NE(message.find(b.phrase), std::string::npos) << message;
  }
  // A polygon above the limit, and lines counted as the reader counts them (\r\n, lone \r).
  // (Built by appending: GCC 12's -Wrestrict misfires on "literal" + std::string.)
  std::string big;
  for (int i = 0; i < 300; ++i) {
    big += "v ";
    big += std::to_string(i);
    big += ' ';
    big += std::to_string(i * i);
    big += " 0\n";
  }
  big += "f";
  for (int i = 1; i <= 300; ++i) {
    big += ' ';
    big += std::to_string(i);
  }
  EXPECT_NE(error_of([&] { parse_obj(big, "m.obj"); }).find("m.obj:301: a face of more than 256"),
            std::string::npos);
  EXPECT_NE(error_of([&] {
              parse_obj("v 0 0 0\r\nv 1 0 0\rv 0 1 0\nf 1 2 4\n", "m.obj");
            }).find("m.obj:4: vertex index out of range"),
            std::string::npos);
}

TEST(mesh_io, ObjPolygonsAndGroupsMerge) {
  // A pentagon (ear clipping) in one group and a triangle in another, relative indices.
  const std::string text =
      "v 0 0 0\nv 2 0 0\nv 3 1 0\nv 1 2 0\nv -1 1 0\ng one\nf 1 2 3 4 5\no two\nf -5 -3 -4\n";
  const TriMesh m = parse_obj(text, "m.obj");
  EXPECT_EQ(m.triangles.size(), 4u);
  EXPECT_EQ(m.vertices.size(), 5u);
  EXPECT_NEAR(double(m.area()), 5 + 1.0, 1e-12);  // the pentagon (5) and the triangle (1)
}

TEST(mesh_io, MalformedStlIsRefused) {
  const TriMesh tri{{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}}, {{0, 1, 2}}};
  const std::string bin = binary_stl(tri);
  const struct {
    std::string bytes, phrase;
  } bad[] = {
      {bin.substr(0, 50), "s.stl: truncated: a binary STL starts with an 84-byte header"},
      {bin.substr(0, 100), "s.stl: truncated: the header says 1 triangles"},
      {bin + "xx", "s.stl: 2 bytes after the last of the 1 triangles"},
      {"solid, says the header" + bin.substr(22, 100), "s.stl: truncated: the header says 1"},
      {bin.substr(0, 80) + std::string(4, '\0'), "s.stl: empty mesh (no triangles)"},
      {binary_stl({{{0, 0, 0}, {1, 0, 0}, {2, 0, 0}}, {{0, 1, 2}}}), "s.stl: zero-area face 1"},
      {binary_stl({{{0, 0, 0}, {1, 0, 0}, {0, Real(NAN), 0}}, {{0, 1, 2}}}),
       "s.stl: NaN or infinite coordinate in triangle 1"},
      {"solid x\nendsolid x\n", "s.stl: empty mesh (no triangles)"},
      {"solid x\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\nvertex 0 1 0\n"
       "vertex 1 1 0\nendloop\nendfacet\nendsolid\n",
       "s.stl:7: expected 'endloop', found 'vertex'"},
      {"solid x\nfacet normal 0 0 nan\n", "s.stl:2: NaN or infinite normal in facet 1"},
      {"solid x\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\nvertex 0 1 zz\n",
       "s.stl:6: not a number: 'zz'"},
      {"solid x\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\nvertex 0 1 0\n"
       "endloop\nendfacet\nendsolid x\ntrailing\n",
       "s.stl:10: expected 'solid' or the end after 'endsolid', found 'trailing'"},
      {"solid x\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\nvertex 0 1 0\n"
       "endloop\nendfacet\n",
       "s.stl:8: truncated: the file ends where 'facet' or 'endsolid' was expected"},
      {"", "s.stl: empty file"},
  };
  for (const auto& b : bad) {
    SCOPED_TRACE(b.bytes.substr(0, 40));
    const std::string message = error_of([&] { parse_stl(b.bytes, "s.stl"); });
    EXPECT_NE(message.find(b.phrase), std::string::npos) << message;
  }
  // Two solids in a row, upper-case keywords, CRLF: read.
  const std::string two =
      "solid a\r\nFACET NORMAL 0 0 1\r\nOUTER LOOP\r\nVERTEX 0 0 0\r\nVERTEX 1 0 0\r\n"
      "VERTEX 0 1 0\r\nENDLOOP\r\nENDFACET\r\nENDSOLID a\r\nsolid b\nendsolid b\n";
  EXPECT_EQ(parse_stl(two, "s.stl").triangles.size(), 1u);
}

}  // namespace
}  // namespace maille

namespace maille {
namespace {

// One parse: the reader triangulates the faces itself. Quads split along the shorter
// diagonal (as tinyobjloader did), larger polygons by ear clipping, non-convex ones included;
// a polygon with no ear is refused at its line.
TEST(mesh_io, ObjFacesAreTriangulatedByTheReader) {
  const TriMesh kite = parse_obj("v 0 0 0\nv 1 -2 0\nv 1.5 0 0\nv 1 2 0\nf 1 2 3 4\n", "k.obj");
  ASSERT_EQ(kite.triangles.size(), 2u);
  EXPECT_EQ(kite.triangles[0], (std::array<std::uint32_t, 3>{0, 1, 2}));  // |v2 - v0| shorter
  EXPECT_EQ(kite.triangles[1], (std::array<std::uint32_t, 3>{0, 2, 3}));
  const TriMesh polygons = read_mesh(kData + "polygons.obj");  // a pentagon and an L hexagon
  EXPECT_EQ(polygons.triangles.size(), 7u);
  EXPECT_NEAR(double(polygons.area()), 5 + 4, 1e-12);
  try {
    parse_obj("v 0 0 0\nv 1 0 0\nv 2 0 0\nv 3 0 0\nv 4 0 0\nf 1 2 3 4 5\n", "flat.obj");
    FAIL() << "accepted";
  } catch (const MeshError& e) {
    EXPECT_NE(std::string(e.what()).find("flat.obj:6: a polygon could not be triangulated"),
              std::string::npos)
        << e.what();
  }
}

}  // namespace
}  // namespace maille
