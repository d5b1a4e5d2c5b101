// STL, binary and ASCII, into a welded TriMesh.
//
// Binary: an 80-byte header, a little-endian uint32 triangle count n, then n records of 50
// bytes (normal, three vertices as 12 little-endian floats, a uint16 attribute). The count is
// checked against the limit and the file size before anything is allocated for it.
// ASCII: "solid NAME" (facet normal n n n / outer loop / vertex x y z x3 / endloop / endfacet)*
// "endsolid NAME", keywords in any case, several solids in a row allowed.
//
// STL stores every triangle's corners separately; corners with exactly the same coordinates
// are welded into one vertex (a hash map), so that a closed surface's shared edges are shared
// indices and TriMesh::closed() can see them. Nothing else is merged: two points 1e-12 apart
// stay two vertices (a tolerance would silently change the surface).
#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <string>
#include <unordered_map>
#include <vector>

#include "mesh_checks.hpp"

namespace maille {

namespace {

using mesh_detail::fail;
using mesh_detail::quote;

constexpr std::size_t kHeaderBytes = 84, kRecordBytes = 50;

// Exactly equal coordinates; -0 and +0 are equal, so they are folded first.
struct Key {
  std::uint64_t x, y, z;
  bool operator==(const Key&) const = default;
};
struct KeyHash {
  std::size_t operator()(const Key& k) const {
    // splitmix64 finaliser per word: coordinates differ mostly in low mantissa bits.
    auto mix = [](std::uint64_t v) {
      v ^= v >> 30, v *= 0xbf58476d1ce4e5b9ULL;
      v ^= v >> 27, v *= 0x94d049bb133111ebULL;
      return v ^ (v >> 31);
    };
    return static_cast<std::size_t>(mix(k.x) ^ mix(k.y + 0x9e3779b97f4a7c15ULL) ^
                                    mix(k.z + 0x3c6ef372fe94f82aULL));
  }
};

class Welder {
 public:
  explicit Welder(std::size_t triangles) {
    map_.reserve(triangles);  // a closed surface has about half as many vertices as triangles
    mesh_.triangles.reserve(triangles);
  }
  std::uint32_t add(Vec3 p) {
    p = {p.x + Real(0), p.y + Real(0), p.z + Real(0)};  // -0 + 0 = +0
    const Key k{std::bit_cast<std::uint64_t>(double(p.x)),
                std::bit_cast<std::uint64_t>(double(p.y)),
                std::bit_cast<std::uint64_t>(double(p.z))};
    const auto [it, inserted] = map_.try_emplace(k, std::uint32_t(mesh_.vertices.size()));
    if (inserted) mesh_.vertices.push_back(p);
    return it->second;
  }
  void triangle(const Vec3 (&p)[3]) {
    mesh_.triangles.push_back({add(p[0]), add(p[1]), add(p[2])});
  }
  TriMesh take() { return std::move(mesh_); }

 private:
  std::unordered_map<Key, std::uint32_t, KeyHash> map_;
  TriMesh mesh_;
};

// Face numbers in messages are 1-based, as a person counts facets.
void check_areas(const TriMesh& mesh, const std::string& name,
                 const std::vector<std::size_t>* facet_lines) {
  const std::size_t t = mesh_detail::first_zero_area(mesh);
  if (t == mesh.triangles.size()) return;
  fail(name, facet_lines ? (*facet_lines)[t] : 0,
       "zero-area face " + std::to_string(t + 1) + " (its corners coincide or are collinear)");
}

float read_float(const unsigned char* p) {
  const std::uint32_t bits = std::uint32_t(p[0]) | std::uint32_t(p[1]) << 8 |
                             std::uint32_t(p[2]) << 16 | std::uint32_t(p[3]) << 24;
  return std::bit_cast<float>(bits);
}

TriMesh parse_binary(std::string_view bytes, const std::string& name) {
  if (bytes.size() < kHeaderBytes)
    fail(name, 0,
         "truncated: a binary STL starts with an 84-byte header, the file has " +
             std::to_string(bytes.size()) + " bytes");
  const auto* data = reinterpret_cast<const unsigned char*>(bytes.data());
  const std::uint64_t n = std::uint64_t(data[80]) | std::uint64_t(data[81]) << 8 |
                          std::uint64_t(data[82]) << 16 | std::uint64_t(data[83]) << 24;
  if (n > mesh_limits::max_triangles)
    fail(name, 0,
         "too many triangles: the header says " + std::to_string(n) + ", the limit is " +
             std::to_string(mesh_limits::max_triangles));
  const std::uint64_t expected = kHeaderBytes + kRecordBytes * n;
  if (bytes.size() < expected)
    fail(name, 0,
         "truncated: the header says " + std::to_string(n) + " triangles (" +
             std::to_string(expected) + " bytes), the file has " + std::to_string(bytes.size()) +
             " bytes");
  if (bytes.size() > expected)
    fail(name, 0,
         std::to_string(bytes.size() - expected) + " bytes after the last of the " +
             std::to_string(n) + " triangles the header announces (not a binary STL?)");
  if (n == 0) fail(name, 0, "empty mesh (no triangles)");

  Welder weld(n);
  for (std::uint64_t t = 0; t < n; ++t) {
    const unsigned char* r = data + kHeaderBytes + kRecordBytes * t;
    float f[12];
    for (int k = 0; k < 12; ++k) f[k] = read_float(r + 4 * k);
    // The normal is not used (the corners' order gives the orientation), but a NaN there is
    // a broken file all the same.
    for (int k = 0; k < 3; ++k)
      if (!std::isfinite(f[k]))
        fail(name, 0, "NaN or infinite normal in triangle " + std::to_string(t + 1));
    for (int k = 3; k < 12; ++k) {
      const std::string problem = mesh_detail::coordinate_problem(f[k]);
      if (!problem.empty()) fail(name, 0, problem + " in triangle " + std::to_string(t + 1));
    }
    const Vec3 p[3] = {{f[3], f[4], f[5]}, {f[6], f[7], f[8]}, {f[9], f[10], f[11]}};
    weld.triangle(p);
  }
  TriMesh mesh = weld.take();
  check_areas(mesh, name, nullptr);
  return mesh;
}

// Whitespace-separated tokens with their line numbers (\n, \r\n and a lone \r end lines).
class Tokens {
 public:
  explicit Tokens(std::string_view text) : text_(text) {}
  // The next token, empty at the end of the text (line() then stays on the last token's line,
  // where a truncated file stops).
  std::string_view next() {
    skip_space();
    const std::size_t start = pos_;
    while (pos_ < text_.size() && !is_space(text_[pos_])) ++pos_;
    if (pos_ > start) token_line_ = line_;
    return text_.substr(start, pos_ - start);
  }
  // The rest of the current line (a solid's name), consumed.
  void skip_line() {
    while (pos_ < text_.size() && text_[pos_] != '\n' && text_[pos_] != '\r') ++pos_;
  }
  std::size_t line() const { return token_line_; }

 private:
  static bool is_space(char c) {
    return c == ' ' || c == '\t' || c == '\n' || c == '\r' || c == '\v' || c == '\f';
  }
  void skip_space() {
    while (pos_ < text_.size() && is_space(text_[pos_])) {
      if (text_[pos_] == '\n' ||
          (text_[pos_] == '\r' && (pos_ + 1 == text_.size() || text_[pos_ + 1] != '\n')))
        ++line_;
      ++pos_;
    }
  }
  std::string_view text_;
  std::size_t pos_ = 0, line_ = 1, token_line_ = 1;
};

bool keyword(std::string_view token, std::string_view lower) {
  return token.size() == lower.size() && std::equal(token.begin(), token.end(), lower.begin(),
                                                    [](char a, char b) { return (a | 0x20) == b; });
}

class AsciiReader {
 public:
  AsciiReader(std::string_view text, const std::string& name) : tokens_(text), name_(name) {}

  TriMesh read() {
    std::string_view t = tokens_.next();
    if (!keyword(t, "solid")) fail(name_, tokens_.line(), "expected 'solid', found " + quote(t));
    while (true) {
      tokens_.skip_line();  // the solid's name
      read_facets();
      tokens_.skip_line();  // the name after endsolid
      t = tokens_.next();
      if (t.empty()) break;
      if (!keyword(t, "solid"))
        fail(name_, tokens_.line(),
             "expected 'solid' or the end after 'endsolid', found " + quote(t));
    }
    if (facets_ == 0) fail(name_, 0, "empty mesh (no triangles)");
    TriMesh mesh = weld_.take();
    check_areas(mesh, name_, &facet_lines_);
    return mesh;
  }

 private:
  // Facets up to and including "endsolid".
  void read_facets() {
    while (true) {
      const std::string_view t = tokens_.next();
      if (keyword(t, "endsolid")) return;
      if (!keyword(t, "facet")) expected("'facet' or 'endsolid'", t);
      if (facets_ == mesh_limits::max_triangles)
        fail(name_, tokens_.line(),
             "too many triangles: more than the limit of " +
                 std::to_string(mesh_limits::max_triangles));
      ++facets_;
      facet_lines_.push_back(tokens_.line());
      expect("normal");
      for (int k = 0; k < 3; ++k)
        if (!std::isfinite(number()))
          fail(name_, tokens_.line(), "NaN or infinite normal in facet " + std::to_string(facets_));
      expect("outer");
      expect("loop");
      Vec3 p[3];
      for (Vec3& v : p) {
        expect("vertex");
        double c[3];
        for (double& x : c) {
          x = number();
          const std::string problem = mesh_detail::coordinate_problem(x);
          if (!problem.empty())
            fail(name_, tokens_.line(), problem + " in facet " + std::to_string(facets_));
        }
        v = {Real(c[0]), Real(c[1]), Real(c[2])};
      }
      expect("endloop");
      expect("endfacet");
      weld_.triangle(p);
    }
  }

  [[noreturn]] void expected(const std::string& what, std::string_view found) {
    if (found.empty())
      fail(name_, tokens_.line(), "truncated: the file ends where " + what + " was expected");
    fail(name_, tokens_.line(), "expected " + what + ", found " + quote(found));
  }
  void expect(std::string_view lower) {
    const std::string_view t = tokens_.next();
    if (keyword(t, lower)) return;
    // Built by appending: GCC 12's -Wrestrict misfires on "'" + std::string(...).
    std::string what(1, '\'');
    what.append(lower).push_back('\'');
    expected(what, t);
  }
  double number() {
    const std::string_view t = tokens_.next();
    if (t.empty()) expected("a number", t);
    double x = 0;
    switch (mesh_detail::parse_number(t, x)) {
      case mesh_detail::Number::ok:
        return x;
      case mesh_detail::Number::out_of_range:
        fail(name_, tokens_.line(), "number out of the range of a double: " + quote(t));
      case mesh_detail::Number::not_a_number:
        break;
    }
    fail(name_, tokens_.line(), "not a number: " + quote(t));
  }

  Tokens tokens_;
  const std::string& name_;
  Welder weld_{0};
  std::size_t facets_ = 0;
  std::vector<std::size_t> facet_lines_;
};

// "solid" first (leading whitespace allowed), as ASCII STL files begin; binary files may begin
// so too (a header is free text), which is why the size test comes first.
bool starts_with_solid(std::string_view bytes) {
  const std::size_t i = bytes.find_first_not_of(" \t\r\n");
  return i != std::string_view::npos && bytes.size() - i >= 5 &&
         keyword(bytes.substr(i, 5), "solid");
}

bool exact_binary_size(std::string_view bytes) {
  if (bytes.size() < kHeaderBytes) return false;
  const auto* d = reinterpret_cast<const unsigned char*>(bytes.data());
  const std::uint64_t n = std::uint64_t(d[80]) | std::uint64_t(d[81]) << 8 |
                          std::uint64_t(d[82]) << 16 | std::uint64_t(d[83]) << 24;
  return bytes.size() == kHeaderBytes + kRecordBytes * n;
}

}  // namespace

namespace mesh_detail {
bool looks_like_binary_stl(std::string_view bytes) {
  return exact_binary_size(bytes);
}
bool looks_like_ascii_stl(std::string_view bytes) {
  if (!starts_with_solid(bytes)) return false;
  for (const std::string_view word : {"facet", "FACET", "endsolid", "ENDSOLID"})
    if (bytes.find(word) != std::string_view::npos) return true;
  return false;
}
}  // namespace mesh_detail

TriMesh parse_stl(std::string_view bytes, const std::string& name) {
  if (bytes.empty()) fail(name, 0, "empty file");
  // Text never holds a NUL; a binary STL always does (its count's high byte, for any count
  // under the limit), so one that starts with "solid" but is cut short is still binary.
  if (!exact_binary_size(bytes) && starts_with_solid(bytes) &&
      bytes.find('\0') == std::string_view::npos)
    return AsciiReader(bytes, name).read();
  return parse_binary(bytes, name);
}

}  // namespace maille
