// Shared reader pieces: see mesh_checks.hpp.
#include "mesh_checks.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <limits>
#include <system_error>

namespace maille::mesh_detail {

void fail(const std::string& name, std::size_t line, const std::string& what) {
  if (line > 0) throw MeshError(name + ":" + std::to_string(line) + ": " + what);
  throw MeshError(name + ": " + what);
}

std::string quote(std::string_view token) {
  constexpr std::size_t kShown = 16;  // a token, never a line of a file that is no mesh
  std::string out = "'";
  for (std::size_t i = 0; i < token.size() && i < kShown; ++i) {
    const auto c = static_cast<unsigned char>(token[i]);
    if (c >= 0x20 && c < 0x7f) {
      out += static_cast<char>(c);
    } else {
      constexpr char hex[] = "0123456789abcdef";
      out += "\\x";
      out += hex[c >> 4];
      out += hex[c & 15];
    }
  }
  if (token.size() > kShown) out += "...";
  return out + "'";
}

namespace {

bool iequals(std::string_view a, std::string_view b) {
  return a.size() == b.size() && std::equal(a.begin(), a.end(), b.begin(), [](char x, char y) {
           return (x | 0x20) == y;  // b is lower case
         });
}

bool is_digit(char c) {
  return c >= '0' && c <= '9';
}

// The grammar above, without the sign (already skipped).
bool decimal_syntax(std::string_view s) {
  std::size_t i = 0, digits = 0;
  while (i < s.size() && is_digit(s[i])) ++i, ++digits;
  if (i < s.size() && s[i] == '.') {
    ++i;
    while (i < s.size() && is_digit(s[i])) ++i, ++digits;
  }
  if (digits == 0) return false;
  if (i < s.size() && (s[i] == 'e' || s[i] == 'E')) {
    ++i;
    if (i < s.size() && (s[i] == '+' || s[i] == '-')) ++i;
    const std::size_t exponent_start = i;
    while (i < s.size() && is_digit(s[i])) ++i;
    if (i == exponent_start) return false;
  }
  return i == s.size();
}

}  // namespace

Number parse_number(std::string_view token, double& value) {
  std::string_view s = token;
  bool negative = false;
  if (!s.empty() && (s[0] == '+' || s[0] == '-')) negative = s[0] == '-', s.remove_prefix(1);
  if (iequals(s, "nan")) {
    value = std::numeric_limits<double>::quiet_NaN();
    return Number::ok;
  }
  if (iequals(s, "inf") || iequals(s, "infinity")) {
    value = negative ? -std::numeric_limits<double>::infinity()
                     : std::numeric_limits<double>::infinity();
    return Number::ok;
  }
  if (!decimal_syntax(s)) return Number::not_a_number;
  // from_chars: exact (correctly rounded) and locale-independent; it takes no '+'.
  double v = 0;
  const auto [end, ec] = std::from_chars(s.data(), s.data() + s.size(), v);
  if (ec == std::errc::result_out_of_range) return Number::out_of_range;
  if (ec != std::errc() || end != s.data() + s.size()) return Number::not_a_number;
  value = negative ? -v : v;
  return Number::ok;
}

std::string coordinate_problem(double x) {
  if (!std::isfinite(x)) return "NaN or infinite coordinate";
  if (std::abs(x) > mesh_limits::max_coordinate) {
    char buf[32];
    const auto r = std::to_chars(buf, buf + sizeof buf, double(mesh_limits::max_coordinate));
    return "coordinate beyond " + std::string(buf, r.ptr);
  }
  return {};
}

std::size_t first_zero_area(const TriMesh& mesh) {
  if (mesh.triangles.empty()) return 0;
  Vec3 lo = mesh.vertices.front(), hi = lo;
  for (const Vec3& v : mesh.vertices) {
    lo = {std::min(lo.x, v.x), std::min(lo.y, v.y), std::min(lo.z, v.z)};
    hi = {std::max(hi.x, v.x), std::max(hi.y, v.y), std::max(hi.z, v.z)};
  }
  // Twice the area against twice the threshold; an exact zero (a repeated vertex, collinear
  // points that cancel) is refused even when the whole mesh is tiny.
  const Real twice_min = 2 * mesh_limits::min_relative_area * norm2(hi - lo);
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
    const auto& tri = mesh.triangles[t];
    const Vec3 a = mesh.vertices[tri[0]];
    const Real twice = norm(cross(mesh.vertices[tri[1]] - a, mesh.vertices[tri[2]] - a));
    if (!(twice > 0) || twice < twice_min) return t;
  }
  return mesh.triangles.size();
}

}  // namespace maille::mesh_detail
