// Geometric obstacles inside the GPU's vertex block descent: see gpu_vbd_obstacles.hpp.
#include "gpu_vbd_obstacles.hpp"

#include <epoxy/gl.h>

#include <algorithm>
#include <cmath>
#include <limits>

#include "../collision/obstacle/geometric_obstacle_view.hpp"
#include "gl_buffers.hpp"

namespace maille::gpu {

namespace {

// 2^-10: the cull's sphere a little larger than the CPU's (as gpu_obstacle.cpp's).
constexpr double kReachMargin = 1.0 + 1.0 / 1024;

// Obstacle o placed at t, as the CPU places it (ObstacleMotion::at in double), in float.
ObstacleRecord record(const Obstacle& o, double t, Real reach) {
  ObstacleRecord r{};
  r.shape = std::uint32_t(o.shape);
  r.shape_parameter = float(shape_parameter(o.shape, o.shape_parameter));
  r.stiffness = float(o.stiffness);
  r.damping = float(o.damping);
  r.friction = float(o.friction);
  r.slip = float(kObstacleSlip);
  r.world_normal = o.world_normal ? 1u : 0u;
  r.moves = o.motion.moves() ? 1u : 0u;
  const double grown = double(reach) * kReachMargin;
  r.reach2 = std::isfinite(grown) ? float(grown * grown) : std::numeric_limits<float>::infinity();
  const shapes::Affine a = o.motion.at(o.place, t);
  float* d[9] = {&r.d00, &r.d01, &r.d02, &r.d10, &r.d11, &r.d12, &r.d20, &r.d21, &r.d22};
  float* in[9] = {&r.i00, &r.i01, &r.i02, &r.i10, &r.i11, &r.i12, &r.i20, &r.i21, &r.i22};
  for (int k = 0; k < 9; ++k) {
    *d[k] = float(a.direct.m[k / 3][k % 3]);
    *in[k] = float(a.inverse.m[k / 3][k % 3]);
  }
  r.tx = float(a.translation.x), r.ty = float(a.translation.y), r.tz = float(a.translation.z);
  const ObstacleMotion::Twist w = o.motion.twist(t);
  r.lx = float(w.linear.x), r.ly = float(w.linear.y), r.lz = float(w.linear.z);
  r.sx = float(w.spin.x), r.sy = float(w.spin.y), r.sz = float(w.spin.z);
  r.cx = float(w.center.x), r.cy = float(w.center.y), r.cz = float(w.center.z);
  return r;
}

}  // namespace

std::uint32_t vbd_obstacle_count(std::span<const Stage* const> stages) {
  std::uint32_t count = 0;
  for (const Stage* st : stages) count += geometric_obstacle_view(*st).obstacle ? 1 : 0;
  return count;
}

GpuVbdObstacles::GpuVbdObstacles() {
  glCreateBuffers(GLsizei(buffers_.size()), buffers_.data());
}

GpuVbdObstacles::~GpuVbdObstacles() {
  if (!forgotten_) glDeleteBuffers(GLsizei(buffers_.size()), buffers_.data());
}

void GpuVbdObstacles::load(const Model& m, std::span<const Stage* const> stages) {
  const std::uint32_t n = m.points.size();
  obstacles_.clear();
  std::vector<std::uint32_t> member(n, 0u);
  Real thinnest = std::numeric_limits<Real>::infinity();
  for (const Stage* st : stages) {
    const GeometricObstacleView view = geometric_obstacle_view(*st);
    if (!view.obstacle) continue;
    const auto bit = std::uint32_t(1) << obstacles_.size();
    for (const std::uint32_t p : view.points) member[p] |= bit;
    obstacles_.push_back({view.obstacle, view.reach});
    thinnest = std::min(thinnest, view.thickness);
  }
  thinnest_ = float(thinnest);
  records_.assign(2 * obstacles_.size(), ObstacleRecord{});
  upload(buffers_[0], records_);
  upload(buffers_[1], member);
  upload(buffers_[2], std::vector<float>(4 * std::size_t(n) * obstacles_.size(), 0.0f));
  upload(buffers_[3], std::vector<std::uint32_t>(n, 0u));
}

void GpuVbdObstacles::place(double t, double t_next) {
  if (obstacles_.empty()) return;
  const std::size_t count = obstacles_.size();
  for (std::size_t o = 0; o < count; ++o) {
    records_[o] = record(*obstacles_[o].obstacle, t, obstacles_[o].reach);
    records_[count + o] = record(*obstacles_[o].obstacle, t_next, obstacles_[o].reach);
  }
  glNamedBufferSubData(buffers_[0], 0, GLsizeiptr(records_.size() * sizeof(ObstacleRecord)),
                       records_.data());
}

void GpuVbdObstacles::bind() const {
  for (unsigned k = 0; k < buffers_.size(); ++k)
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, unsigned(Buf::vbd_obstacles) + k, buffers_[k]);
}

}  // namespace maille::gpu
