// OBJ through tinyobjloader, behind a strict scan of our own.
//
// tinyobjloader is lenient by design: "1.5abc" reads as 1.5, "nan" as 0, an unknown statement
// is skipped, an index past the vertices read so far is kept and later read out of bounds by
// its triangulation, and atoi() overflows on long indices. So the text is scanned first, line
// by line exactly as tinyobjloader splits it (\n, \r\n, lone \r), and every statement it would
// act on is checked:
//
//   v x y z [w | r g b]   numbers (grammar in mesh_checks.hpp), coordinates finite and in range
//   vt, vn, vp            numbers (read by tinyobjloader, not used)
//   f / l / p             refs v, v/vt, v//vn, v/vt/vn: integers, not 0, inside what is
//                         defined so far (negative = relative); faces of 3..256 vertices
//   g o s usemtl mtllib   allowed; anything else is an unknown statement
//
// and the sizes are counted against mesh_limits before tinyobjloader allocates anything.
// Materials are not read: usemtl / mtllib lines (and nameless groups, which only make
// tinyobjloader warn) are turned into comments in the copy it parses, so that any warning or
// error it still gives is a real one and refuses the file.
//
// tinyobjloader supplies the faces: polygons triangulated (its ear clipping; a polygon it
// cannot triangulate leaves fewer than n - 2 triangles, which is refused), every group and
// object merged in file order. The coordinates come from the scan: std::from_chars rounds
// correctly, where tinyobjloader's digit-by-digit conversion is off by an ulp or two, and
// to_obj -> parse_obj must give the same doubles back.
#include <tiny_obj_loader.h>

#include <algorithm>
#include <array>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <istream>
#include <streambuf>
#include <string>
#include <vector>

#include "mesh_checks.hpp"

namespace maille {

namespace {

using mesh_detail::fail;
using mesh_detail::quote;

// The fields of one line, split at spaces and tabs as tinyobjloader splits them.
class Fields {
 public:
  explicit Fields(std::string_view line) : line_(line) {}
  std::string_view next() {
    while (pos_ < line_.size() && (line_[pos_] == ' ' || line_[pos_] == '\t')) ++pos_;
    const std::size_t start = pos_;
    while (pos_ < line_.size() && line_[pos_] != ' ' && line_[pos_] != '\t') ++pos_;
    return line_.substr(start, pos_ - start);
  }

 private:
  std::string_view line_;
  std::size_t pos_ = 0;
};

struct Scan {
  std::vector<Vec3> positions;
  std::vector<std::size_t> face_lines;           // line of each `f`, in file order
  std::vector<std::size_t> face_first_triangle;  // its first triangle once triangulated
  std::size_t triangles = 0;
  std::string text;  // the copy tinyobjloader parses (same length and lines)
};

class Scanner {
 public:
  Scanner(std::string_view text, const std::string& name) : in_(text), name_(name) {
    scan_.text.assign(text);
  }

  Scan run() {
    std::size_t pos = 0;
    while (pos < in_.size()) {
      ++line_;
      const std::size_t start = pos;
      while (pos < in_.size() && in_[pos] != '\n' && in_[pos] != '\r') ++pos;
      const std::string_view line = in_.substr(start, pos - start);
      if (pos < in_.size())
        pos += (in_[pos] == '\r' && pos + 1 < in_.size() && in_[pos + 1] == '\n') ? 2 : 1;
      statement(line, start);
    }
    if (scan_.triangles == 0) fail(name_, 0, "empty mesh (no triangles)");
    return std::move(scan_);
  }

 private:
  void statement(std::string_view line, std::size_t offset) {
    // tinyobjloader reads a line as a C string: a NUL would end it early, hiding the rest.
    if (line.find('\0') != std::string_view::npos)
      fail(name_, line_, "NUL byte in the text (a binary file?)");
    const std::size_t first = line.find_first_not_of(" \t");
    if (first == std::string_view::npos || line[first] == '#') return;
    Fields fields(line);
    const std::string_view keyword = fields.next();
    if (keyword == "v") {
      vertex(fields);
    } else if (keyword == "vt" || keyword == "vp") {
      numbers(fields, 1, 3, keyword);
    } else if (keyword == "vn") {
      numbers(fields, 3, 3, keyword);
    } else if (keyword == "f") {
      face(fields);
    } else if (keyword == "l") {
      refs(fields, 2, "a line");
    } else if (keyword == "p") {
      refs(fields, 1, "a point");
    } else if (keyword == "g") {
      if (fields.next().empty()) scan_.text[offset + first] = '#';
    } else if (keyword == "o") {
    } else if (keyword == "s") {
      smoothing(fields);
    } else if (keyword == "usemtl" || keyword == "mtllib") {
      scan_.text[offset + first] = '#';
    } else if (known_) {
      fail(name_, line_, "unknown statement " + quote(keyword));
    } else {  // nothing of a mesh yet: quote none of it (a path may lead to any file)
      fail(name_, line_,
           "not a mesh file: its first statement is none of OBJ's (v, vt, vn, vp, f, l, p, g, o, "
           "s, usemtl, mtllib), and it is no STL ('solid' or 84 + 50 n bytes)");
    }
    known_ = true;
  }

  void count_vertex_like() {
    if (++vertex_like_ > mesh_limits::max_vertices)
      fail(name_, line_,
           "too many vertices (v, vt, vn, vp together): the limit is " +
               std::to_string(mesh_limits::max_vertices));
  }

  double number(std::string_view token) {
    double x = 0;
    switch (mesh_detail::parse_number(token, x)) {
      case mesh_detail::Number::ok:
        return x;
      case mesh_detail::Number::out_of_range:
        fail(name_, line_, "number out of the range of a double: " + quote(token));
      case mesh_detail::Number::not_a_number:
        break;
    }
    fail(name_, line_, "not a number: " + quote(token));
  }

  void vertex(Fields& fields) {
    count_vertex_like();
    double c[7];
    int n = 0;
    for (std::string_view t = fields.next(); !t.empty(); t = fields.next()) {
      if (n == 7) fail(name_, line_, "a vertex has 3, 4 (x y z w) or 6 (x y z r g b) numbers");
      c[n++] = number(t);
    }
    if (n != 3 && n != 4 && n != 6)
      fail(name_, line_,
           "a vertex has 3, 4 (x y z w) or 6 (x y z r g b) numbers, found " + std::to_string(n));
    const std::size_t index = scan_.positions.size() + 1;
    for (int k = 0; k < 3; ++k) {
      const std::string problem = mesh_detail::coordinate_problem(c[k]);
      if (!problem.empty()) fail(name_, line_, problem + " (vertex " + std::to_string(index) + ")");
    }
    for (int k = 3; k < n; ++k)
      if (!std::isfinite(c[k]))
        fail(name_, line_, "NaN or infinite value (vertex " + std::to_string(index) + ")");
    scan_.positions.push_back({Real(c[0]), Real(c[1]), Real(c[2])});
  }

  void numbers(Fields& fields, int min, int max, std::string_view keyword) {
    count_vertex_like();
    int n = 0;
    for (std::string_view t = fields.next(); !t.empty(); t = fields.next()) {
      if (!std::isfinite(number(t)))
        fail(name_, line_, "NaN or infinite value in " + quote(keyword));
      ++n;
    }
    if (n < min || n > max)
      fail(name_, line_,
           quote(keyword) + " takes " + std::to_string(min) +
               (min == max ? "" : " to " + std::to_string(max)) + " numbers, found " +
               std::to_string(n));
    if (keyword == "vt") ++texcoords_;
    if (keyword == "vn") ++normals_;
  }

  // One index of a reference: [+-]digits, not 0, inside the `defined` items read so far
  // (negative: counted back from the last one).
  void index(std::string_view token, std::size_t defined, const char* what) {
    std::string_view digits = token;
    const bool negative = !digits.empty() && digits[0] == '-';
    if (!digits.empty() && (digits[0] == '+' || digits[0] == '-')) digits.remove_prefix(1);
    if (digits.empty() ||
        !std::all_of(digits.begin(), digits.end(), [](char c) { return c >= '0' && c <= '9'; }))
      fail(name_, line_, "not a number: " + quote(token) + " (a " + what + " index)");
    unsigned long long k = 0;
    const std::errc ec = std::from_chars(digits.data(), digits.data() + digits.size(), k).ec;
    if (ec == std::errc() && k == 0)
      fail(name_, line_, std::string(what) + " index out of range: 0 (OBJ indices start at 1)");
    if (ec != std::errc() || k > defined)
      fail(name_, line_,
           std::string(what) + " index out of range: " + quote(token) + " (" +
               std::to_string(defined) + (negative ? " defined before it)" : " defined so far)"));
  }

  // v, v/vt, v//vn or v/vt/vn.
  void ref(std::string_view token) {
    std::string_view part[3];
    int parts = 0;
    std::size_t start = 0;
    while (true) {
      const std::size_t slash = token.find('/', start);
      if (parts == 3) fail(name_, line_, "bad vertex reference " + quote(token));
      part[parts++] = token.substr(
          start, slash == std::string_view::npos ? std::string_view::npos : slash - start);
      if (slash == std::string_view::npos) break;
      start = slash + 1;
    }
    const bool ok = !part[0].empty() && (parts < 2 || !part[1].empty() || parts == 3) &&
                    (parts < 3 || !part[2].empty());
    if (!ok) fail(name_, line_, "bad vertex reference " + quote(token));
    index(part[0], scan_.positions.size(), "vertex");
    if (parts >= 2 && !part[1].empty()) index(part[1], texcoords_, "texture coordinate");
    if (parts == 3) index(part[2], normals_, "normal");
  }

  std::size_t refs(Fields& fields, std::size_t min, const char* what) {
    std::size_t n = 0;
    for (std::string_view t = fields.next(); !t.empty(); t = fields.next()) {
      if (n == mesh_limits::max_polygon_vertices)
        fail(name_, line_,
             std::string(what) + " of more than " +
                 std::to_string(mesh_limits::max_polygon_vertices) + " vertices (the limit)");
      ref(t);
      ++n;
    }
    if (n < min)
      fail(name_, line_,
           std::string(what) + " needs at least " + std::to_string(min) + " vertices, found " +
               std::to_string(n));
    return n;
  }

  void face(Fields& fields) {
    const std::size_t n = refs(fields, 3, "a face");
    if (scan_.triangles + (n - 2) > mesh_limits::max_triangles)
      fail(name_, line_,
           "too many triangles: more than the limit of " +
               std::to_string(mesh_limits::max_triangles));
    scan_.face_lines.push_back(line_);
    scan_.face_first_triangle.push_back(scan_.triangles);
    scan_.triangles += n - 2;
  }

  // "s off", "s on" or a group number (tinyobjloader reads it with atoi: keep it short).
  void smoothing(Fields& fields) {
    const std::string_view t = fields.next();
    const bool number = !t.empty() && t.size() <= 9 && std::all_of(t.begin(), t.end(), [](char c) {
      return c >= '0' && c <= '9';
    });
    if (!(t.empty() || t == "off" || t == "on" || number) || !fields.next().empty())
      fail(name_, line_, "bad smoothing group (s off, s on or s N)");
  }

  std::string_view in_;
  const std::string& name_;
  Scan scan_;
  std::size_t line_ = 0;
  std::size_t vertex_like_ = 0, texcoords_ = 0, normals_ = 0;
  bool known_ = false;  // a statement of OBJ was read
};

// An istream over the scan's copy, without another copy (ObjReader::ParseFromString copies).
class TextBuffer : public std::streambuf {
 public:
  explicit TextBuffer(std::string& text) {
    setg(text.data(), text.data(), text.data() + text.size());
  }
};

std::string trimmed(std::string s) {
  while (!s.empty() && (s.back() == '\n' || s.back() == '.' || s.back() == ' ')) s.pop_back();
  std::replace(s.begin(), s.end(), '\n', ' ');
  return s;
}

}  // namespace

TriMesh parse_obj(std::string_view text, const std::string& name) {
  if (text.empty()) fail(name, 0, "empty file");
  Scan scan = Scanner(text, name).run();

  tinyobj::attrib_t attrib;
  std::vector<tinyobj::shape_t> shapes;
  std::vector<tinyobj::material_t> materials;
  std::string warn, err;
  {
    TextBuffer buffer(scan.text);
    std::istream in(&buffer);
    const bool ok = tinyobj::LoadObj(&attrib, &shapes, &materials, &warn, &err, &in,
                                     /*readMatFn=*/nullptr, /*triangulate=*/true,
                                     /*default_vcols_fallback=*/false);
    if (!ok || !err.empty()) fail(name, 0, "tinyobjloader: " + trimmed(err));
    if (!warn.empty()) fail(name, 0, "tinyobjloader: " + trimmed(warn));
  }
  scan.text = {};
  // The scan and tinyobjloader must agree on what the file holds; a difference is a gap in the
  // scan (the fuzzer's business), refused rather than trusted.
  if (attrib.vertices.size() != 3 * scan.positions.size())
    fail(name, 0,
         "tinyobjloader read " + std::to_string(attrib.vertices.size() / 3) +
             " vertices where the check counted " + std::to_string(scan.positions.size()));

  TriMesh mesh;
  mesh.vertices = std::move(scan.positions);
  mesh.triangles.reserve(scan.triangles);
  const std::size_t nv = mesh.vertices.size();
  for (const tinyobj::shape_t& shape : shapes) {
    const auto& idx = shape.mesh.indices;
    if (idx.size() % 3 != 0 || idx.size() / 3 > scan.triangles - mesh.triangles.size())
      fail(name, 0, "tinyobjloader made more triangles than the faces allow");
    for (std::size_t i = 0; i < idx.size(); i += 3) {
      std::array<std::uint32_t, 3> t{};
      for (int k = 0; k < 3; ++k) {
        const int v = idx[i + k].vertex_index;
        if (v < 0 || static_cast<std::size_t>(v) >= nv)
          fail(name, 0, "tinyobjloader made a vertex index out of range: " + std::to_string(v));
        t[k] = static_cast<std::uint32_t>(v);
      }
      mesh.triangles.push_back(t);
    }
  }
  if (mesh.triangles.size() != scan.triangles)
    fail(name, 0,
         "a polygon could not be triangulated (" + std::to_string(scan.triangles) +
             " triangles expected from the faces, tinyobjloader made " +
             std::to_string(mesh.triangles.size()) + ")");

  // Every face gave n - 2 triangles in file order, so a triangle's face is found by its index.
  const std::size_t t = mesh_detail::first_zero_area(mesh);
  if (t < mesh.triangles.size()) {
    const auto& first = scan.face_first_triangle;
    const std::size_t f = std::upper_bound(first.begin(), first.end(), t) - first.begin() - 1;
    fail(name, scan.face_lines[f],
         "zero-area face " + std::to_string(f + 1) + " (its corners coincide or are collinear)");
  }
  return mesh;
}

}  // namespace maille
