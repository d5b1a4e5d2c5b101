// Canonical shapes (include/maille/shapes.hpp): the shape table's lookups, the distance
// functions from the shared law file, and the placements.
#include <cmath>
#include <numbers>
#include <stdexcept>
#include <string>
#include <vector>

#include "maille/shape_keys.hpp"
#include "maille/shapes.hpp"
#include "maille/shared_laws.hpp"

namespace maille {

// The shape table's lookups (the table itself: shape_table.cpp).

const ShapeRow& shape_row(ShapeKind s) {
  const auto table = shape_table();
  if (std::size_t(s) >= table.size())
    throw std::logic_error("shape_row: no shape numbered " + std::to_string(int(s)));
  return table[std::size_t(s)];
}

std::optional<ShapeKind> parse_shape(std::string_view name) {
  const auto table = shape_table();
  for (std::size_t i = 0; i < table.size(); ++i)
    if (table[i].name == name) return ShapeKind(i);
  return std::nullopt;
}

ShapeKind shape_kind(std::string_view name) {
  if (const auto s = parse_shape(name)) return *s;
  throw std::invalid_argument("no shape named '" + std::string(name) +
                              "' (the shapes: " + shape_name_list() + ")");
}

std::string_view to_string(ShapeKind s) {
  return shape_row(s).name;
}

std::span<const std::string_view> shape_names() {
  static const std::vector<std::string_view> names = [] {
    std::vector<std::string_view> out;
    for (const ShapeRow& row : shape_table()) out.push_back(row.name);
    return out;
  }();
  return names;
}

std::string shape_name_list(std::string_view separator) {
  std::string out;
  for (const ShapeRow& row : shape_table()) {
    if (!out.empty()) out += separator;
    out += row.name;
  }
  return out;
}

namespace shape_key_detail {
std::span<const ShapeKind> parameter_shapes() {
  static const std::vector<ShapeKind> shapes = [] {
    std::vector<ShapeKind> out;
    const auto table = shape_table();
    for (std::size_t i = table.size(); i-- > 0;)
      if (table[i].parameter) out.push_back(ShapeKind(i));
    return out;
  }();
  return shapes;
}
}  // namespace shape_key_detail

std::string_view shape_docs() {
  static const std::string docs = [] {
    std::string out = "canonical shapes of unit size: ";
    for (const ShapeRow& row : shape_table()) {
      if (&row != shape_table().data()) out += "; ";
      out.append("`").append(row.name).append("`: ").append(row.doc);
    }
    return out;
  }();
  return docs;
}

Real shape_parameter(ShapeKind s, std::optional<Real> p) {
  const ShapeRow& row = shape_row(s);
  return p ? *p : row.parameter ? row.parameter->fallback : Real(0);
}

}  // namespace maille

namespace maille::shapes {

// ---------------------------------------------------------------------------------------------

Affine Affine::from(const Vec3& position, const Vec3& rotation_degrees, const Vec3& scale) {
  constexpr double deg = std::numbers::pi / 180;
  auto rot = [](int axis, double angle) {
    const Real c = Real(std::cos(angle)), s = Real(std::sin(angle));
    Mat3 m = Mat3::identity();
    const int i = (axis + 1) % 3, j = (axis + 2) % 3;
    m.m[i][i] = c, m.m[i][j] = -s, m.m[j][i] = s, m.m[j][j] = c;
    return m;
  };
  auto mul = [](const Mat3& a, const Mat3& b) {
    Mat3 r{};
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j)
        for (int k = 0; k < 3; ++k) r.m[i][j] += a.m[i][k] * b.m[k][j];
    return r;
  };
  const Mat3 R = mul(rot(2, rotation_degrees.z * deg),
                     mul(rot(1, rotation_degrees.y * deg), rot(0, rotation_degrees.x * deg)));
  Mat3 S = Mat3::identity(), Si = Mat3::identity();
  S.m[0][0] = scale.x, S.m[1][1] = scale.y, S.m[2][2] = scale.z;
  Si.m[0][0] = 1 / scale.x, Si.m[1][1] = 1 / scale.y, Si.m[2][2] = 1 / scale.z;
  Mat3 Rt{};
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) Rt.m[i][j] = R.m[j][i];
  Affine a;
  a.direct = mul(R, S);
  a.inverse = mul(Si, Rt);
  a.translation = position;
  return a;
}

Vec3 Affine::normal_to_world(const Vec3& n) const {
  return law::normal_to_world(inverse, n);
}

Affine Affine::moved(const Mat3& R, const Vec3& center, const Vec3& offset) const {
  Affine a;
  a.direct = R * direct;
  a.inverse = inverse * transpose(R);  // R is orthogonal: R^-1 = R^T
  a.translation = R * (translation - center) + center + offset;
  return a;
}

Mat3 rotation(const Vec3& k, double angle) {
  const Real c = Real(std::cos(angle)), s = Real(std::sin(angle)), t = 1 - c;
  Mat3 r;
  r.m[0][0] = c + t * k.x * k.x, r.m[0][1] = t * k.x * k.y - s * k.z;
  r.m[0][2] = t * k.x * k.z + s * k.y;
  r.m[1][0] = t * k.y * k.x + s * k.z, r.m[1][1] = c + t * k.y * k.y;
  r.m[1][2] = t * k.y * k.z - s * k.x;
  r.m[2][0] = t * k.z * k.x - s * k.y, r.m[2][1] = t * k.z * k.y + s * k.x;
  r.m[2][2] = c + t * k.z * k.z;
  return r;
}

Distance canonical(ShapeKind s, const Vec3& p, std::optional<Real> parameter) {
  Distance d;
  d.signed_distance = law::canonical_distance(int(s), p, shape_parameter(s, parameter), d.normal);
  return d;
}

}  // namespace maille::shapes
