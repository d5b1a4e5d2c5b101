// OBJ, parsed once by our own strict scan: every line is read and checked, and the faces are
// triangulated here. (It used to be scanned here and parsed again by tinyobjloader, whose
// leniency - "1.5abc" as 1.5, "nan" as 0, unknown statements skipped, out-of-range indices read
// out of bounds, atoi overflows - is why the scan existed; the scan already read everything.)
//
//   v x y z [w | r g b]   numbers (grammar in mesh_checks.hpp), coordinates finite and in range
//   vt, vn, vp            numbers (checked, not used)
//   f / l / p             refs v, v/vt, v//vn, v/vt/vn: integers, not 0, inside what is
//                         defined so far (negative = relative); faces of 3..256 vertices
//   g o s usemtl mtllib   allowed (materials are not read); anything else is an unknown statement
//
// Lines end at \n, \r\n or a lone \r. Sizes are counted against mesh_limits before anything is
// allocated for them. Every group and object is merged in file order. Triangles are kept;
// quads are split as tinyobjloader split them, along the shorter diagonal ((0, 1, 2), (0, 2, 3)
// when |v2 - v0| < |v3 - v1|, else (0, 1, 3), (1, 2, 3)), so the meshes of examples/models read
// to the same triangles as before (checked when the reader changed); larger polygons are cut by
// ear clipping in the plane of their Newell normal (the same surface as before, not always the
// same triangles); a polygon with no ear left (self-intersecting, or flat) is refused at its
// line. Coordinates come from std::from_chars,
// correctly rounded, so to_obj -> parse_obj gives the same doubles back.
#include <algorithm>
#include <array>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "mesh_checks.hpp"

namespace maille {

namespace {

using mesh_detail::fail;
using mesh_detail::quote;

// The fields of one line, split at spaces and tabs.
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
  std::vector<std::uint32_t> face_start;         // [faces + 1]: face f's corners in `corners`
  std::vector<std::uint32_t> corners;            // vertex indices (0-based, resolved)
  std::size_t triangles = 0;
};

class Scanner {
 public:
  Scanner(std::string_view text, const std::string& name) : in_(text), name_(name) {
    scan_.face_start.push_back(0);
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
      statement(line);
    }
    if (scan_.triangles == 0) fail(name_, 0, "empty mesh (no triangles)");
    return std::move(scan_);
  }

 private:
  void statement(std::string_view line) {
    // A NUL has no place in OBJ text: a binary file read as OBJ.
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
    } else if (keyword == "g" || keyword == "o" || keyword == "usemtl" || keyword == "mtllib") {
    } else if (keyword == "s") {
      smoothing(fields);
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
  // (negative: counted back from the last one). Returns it 0-based.
  std::size_t index(std::string_view token, std::size_t defined, const char* what) {
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
    return negative ? defined - k : k - 1;
  }

  // v, v/vt, v//vn or v/vt/vn; returns the vertex, 0-based.
  std::size_t ref(std::string_view token) {
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
    const std::size_t vertex = index(part[0], scan_.positions.size(), "vertex");
    if (parts >= 2 && !part[1].empty()) index(part[1], texcoords_, "texture coordinate");
    if (parts == 3) index(part[2], normals_, "normal");
    return vertex;
  }

  // The references of a face, line or point; a face's vertices go to `corners` (the caller
  // keeps them or drops them).
  std::size_t refs(Fields& fields, std::size_t min, const char* what) {
    std::size_t n = 0;
    corners_.clear();
    for (std::string_view t = fields.next(); !t.empty(); t = fields.next()) {
      if (n == mesh_limits::max_polygon_vertices)
        fail(name_, line_,
             std::string(what) + " of more than " +
                 std::to_string(mesh_limits::max_polygon_vertices) + " vertices (the limit)");
      corners_.push_back(static_cast<std::uint32_t>(ref(t)));
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
    scan_.corners.insert(scan_.corners.end(), corners_.begin(), corners_.end());
    scan_.face_start.push_back(static_cast<std::uint32_t>(scan_.corners.size()));
  }

  // "s off", "s on" or a group number (short: a reader using atoi would overflow).
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
  bool known_ = false;                  // a statement of OBJ was read
  std::vector<std::uint32_t> corners_;  // the current statement's vertices
};

// A polygon's triangles into `out` (see the file's comment); false when no ear is left.
bool triangulate(const std::vector<Vec3>& x, std::span<const std::uint32_t> poly,
                 std::vector<std::array<std::uint32_t, 3>>& out) {
  const std::size_t n = poly.size();
  if (n == 3) {
    out.push_back({poly[0], poly[1], poly[2]});
    return true;
  }
  if (n == 4) {
    const Real d02 = norm2(x[poly[2]] - x[poly[0]]), d13 = norm2(x[poly[3]] - x[poly[1]]);
    if (d02 < d13) {
      out.push_back({poly[0], poly[1], poly[2]});
      out.push_back({poly[0], poly[2], poly[3]});
    } else {
      out.push_back({poly[0], poly[1], poly[3]});
      out.push_back({poly[1], poly[2], poly[3]});
    }
    return true;
  }
  // The polygon in the plane of its Newell normal, counter-clockwise seen from the normal.
  Vec3 normal{};
  for (std::size_t k = 0; k < n; ++k) {
    const Vec3& p = x[poly[k]];
    const Vec3& q = x[poly[(k + 1) % n]];
    normal += Vec3{(p.y - q.y) * (p.z + q.z), (p.z - q.z) * (p.x + q.x), (p.x - q.x) * (p.y + q.y)};
  }
  if (!(norm(normal) > 0)) return false;
  const Vec3 w = normal / norm(normal);
  const Vec3 a = std::abs(w.x) > Real(0.9) ? Vec3{0, 1, 0} : Vec3{1, 0, 0};
  const Vec3 u = cross(a, w) / norm(cross(a, w));
  const Vec3 v = cross(w, u);
  std::vector<std::array<Real, 2>> p(n);
  for (std::size_t k = 0; k < n; ++k) p[k] = {dot(x[poly[k]], u), dot(x[poly[k]], v)};
  auto turn = [&](std::size_t i, std::size_t j, std::size_t k) {  // > 0: counter-clockwise
    return (p[j][0] - p[i][0]) * (p[k][1] - p[i][1]) - (p[j][1] - p[i][1]) * (p[k][0] - p[i][0]);
  };
  std::vector<std::size_t> left(n);
  for (std::size_t k = 0; k < n; ++k) left[k] = k;
  while (left.size() > 3) {
    bool clipped = false;
    for (std::size_t e = 0; e < left.size() && !clipped; ++e) {
      const std::size_t i = left[(e + left.size() - 1) % left.size()], j = left[e],
                        k = left[(e + 1) % left.size()];
      if (!(turn(i, j, k) > 0)) continue;  // a reflex or flat corner is no ear
      bool empty = true;
      for (const std::size_t m : left)
        if (m != i && m != j && m != k && turn(i, j, m) >= 0 && turn(j, k, m) >= 0 &&
            turn(k, i, m) >= 0)
          empty = false;
      if (!empty) continue;
      out.push_back({poly[i], poly[j], poly[k]});
      left.erase(left.begin() + std::ptrdiff_t(e));
      clipped = true;
    }
    if (!clipped) return false;
  }
  if (!(turn(left[0], left[1], left[2]) > 0)) return false;
  out.push_back({poly[left[0]], poly[left[1]], poly[left[2]]});
  return true;
}

}  // namespace

TriMesh parse_obj(std::string_view text, const std::string& name) {
  if (text.empty()) fail(name, 0, "empty file");
  Scan scan = Scanner(text, name).run();

  TriMesh mesh;
  mesh.vertices = std::move(scan.positions);
  mesh.triangles.reserve(scan.triangles);
  for (std::size_t f = 0; f + 1 < scan.face_start.size(); ++f) {
    const std::span<const std::uint32_t> poly(scan.corners.data() + scan.face_start[f],
                                              scan.face_start[f + 1] - scan.face_start[f]);
    if (!triangulate(mesh.vertices, poly, mesh.triangles))
      fail(name, scan.face_lines[f],
           "a polygon could not be triangulated (face " + std::to_string(f + 1) + ", " +
               std::to_string(poly.size()) + " vertices: self-intersecting or flat)");
  }

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
