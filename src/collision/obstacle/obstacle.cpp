// What the three obstacle methods share (include/maille/obstacle.hpp): the
// rigid motion, the colliding points, the obstacle's mesh and the dispatch on the method.
#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>

#include "maille/obstacle.hpp"

namespace maille {

namespace {

constexpr double kTau = 2 * std::numbers::pi;

Vec3 unit(const Vec3& a) {
  const Real l = norm(a);
  return l > 0 ? a / l : Vec3{0, 1, 0};
}

}  // namespace

shapes::Affine ObstacleMotion::at(const shapes::Affine& base, double t) const {
  switch (kind) {
    case Kind::none:
      return base;
    case Kind::rotate:
      return base.moved(shapes::rotation(unit(axis), kTau * frequency * t), center, {});
    case Kind::translate:
      return base.moved(Mat3::identity(), {}, velocity * Real(t));
    case Kind::oscillate: {
      const double a = kTau * frequency * t + phase;
      return base.moved(Mat3::identity(), {},
                        amplitude * Real(std::sin(a) - std::sin(double(phase))));
    }
  }
  return base;
}

Vec3 ObstacleMotion::velocity_at(const Vec3& x, double t) const {
  switch (kind) {
    case Kind::none:
      return {};
    case Kind::rotate:  // omega x (x - c): a rigid rotation about the axis through c
      return cross(unit(axis) * Real(kTau * frequency), x - center);
    case Kind::translate:
      return velocity;
    case Kind::oscillate:
      return amplitude * Real(kTau * frequency * std::cos(kTau * frequency * t + phase));
  }
  return {};
}

ObstacleMotion::Twist ObstacleMotion::twist(double t) const {
  switch (kind) {
    case Kind::none:
      return {};
    case Kind::rotate:
      return {{}, unit(axis) * Real(kTau * frequency), center};
    case Kind::translate:
    case Kind::oscillate:
      return {velocity_at({}, t), {}, {}};
  }
  return {};
}

TriMesh obstacle_mesh(const Obstacle& o) {
  if (o.mesh) return *o.mesh;
  return tessellate(o.shape, o.resolution, o.shape_parameter);
}

std::vector<std::uint32_t> colliding_points(const Model& m, const Obstacle& o) {
  std::vector<std::uint8_t> in(m.points.size(), o.collides_with.empty() ? 1 : 0);
  for (const auto& name : o.collides_with) {
    const Group* g = m.group(name);
    if (!g) throw std::invalid_argument("obstacle '" + o.name + "': no group named '" + name + "'");
    std::fill(in.begin() + g->first, in.begin() + g->first + g->count, 1);
  }
  std::vector<std::uint32_t> set;
  for (std::uint32_t p = 0; p < m.points.size(); ++p)
    if (in[p] && m.points.inv_mass[p] > 0) set.push_back(p);
  if (set.empty())
    throw std::invalid_argument("obstacle '" + o.name + "': no free point collides with it");
  return set;
}

std::string obstacle_stage_name(const Obstacle& o) {
  return std::string(kObstacleStagePrefix) + o.name;
}

Phase obstacle_phase(ObstacleMethod m) {
  return m == ObstacleMethod::facets ? Phase::response : Phase::forces;
}

std::unique_ptr<Stage> make_obstacle_stage(const Model& m, const Obstacle& o) {
  if (const StageProblem p = check_obstacle(m, o)) throw std::invalid_argument(p.message);
  switch (o.method) {
    case ObstacleMethod::geometric:
      return make_geometric_obstacle_stage(m, o);
    case ObstacleMethod::facets:
      return make_facet_obstacle_stage(m, o);
    case ObstacleMethod::conditional:
      return make_conditional_obstacle_stage(m, o);
  }
  throw std::invalid_argument("obstacle '" + o.name + "': unknown method");
}

}  // namespace maille
