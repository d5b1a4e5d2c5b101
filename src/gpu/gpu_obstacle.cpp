// The geometric obstacle stage on the GPU: see gpu_obstacle.hpp.
#include "gpu_obstacle.hpp"

#include <epoxy/gl.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include "../collision/obstacle/geometric_obstacle_view.hpp"
#include "gl_buffers.hpp"

namespace maille::gpu {

namespace {

// 2^-10: the cull's sphere a little larger than the CPU's, so that float rounding of |x - t|
// never drops a point the CPU tests (a larger sphere only tests more points).
constexpr double kReachMargin = 1.0 + 1.0 / 1024;

}  // namespace

std::string GpuGeometricObstacle::check(const Stage& st) {
  if (geometric_obstacle_view(st).obstacle) return {};
  return "stage '" + st.name() +
         "' has no GPU version: of [[obstacle]]'s methods the GPU runs method = \"geometric\" "
         "(facets and conditional obstacles run on the CPU): use method = \"geometric\" or run "
         "this scene with --backend cpu";
}

GpuGeometricObstacle::GpuGeometricObstacle(const Stage& st)
    : contacts_("gpu geometric obstacle", obstacle_contacts_shader()) {
  const GeometricObstacleView view = geometric_obstacle_view(st);
  obstacle_ = view.obstacle;
  points_ = std::uint32_t(view.points.size());
  const double reach = double(view.reach) * kReachMargin;
  reach2_ = std::isfinite(reach) ? float(reach * reach) : std::numeric_limits<float>::infinity();
  glCreateBuffers(1, &buffer_);
  upload(buffer_, std::vector<std::uint32_t>(view.points.begin(), view.points.end()),
         GL_STATIC_DRAW);
  const Obstacle& o = *obstacle_;
  contacts_.set("u_shape", unsigned(o.shape));
  contacts_.set("u_shape_parameter", float(shape_parameter(o.shape, o.shape_parameter)));
  contacts_.set("u_stiffness", float(o.stiffness));
  contacts_.set("u_damping", float(o.damping));
  contacts_.set_flag("u_world_normal", o.world_normal);
  contacts_.set("u_friction", float(o.friction));
  contacts_.set("u_slip", float(kObstacleSlip));
  contacts_.set("u_reach2", reach2_);
  contacts_.set_flag("u_moves", o.motion.moves());
}

GpuGeometricObstacle::~GpuGeometricObstacle() {
  glDeleteBuffers(1, &buffer_);
}

void GpuGeometricObstacle::place(Kernel& k, double t) const {
  const Obstacle& o = *obstacle_;
  const shapes::Affine a = o.motion.at(o.place, t);
  k.set("u_direct", a.direct);
  k.set("u_inverse", a.inverse);
  k.set("u_translation", a.translation);
  const ObstacleMotion::Twist w = o.motion.twist(t);
  k.set("u_linear", w.linear);
  k.set("u_spin", w.spin);
  k.set("u_spin_center", w.center);
}

void GpuGeometricObstacle::evaluate(double t) {
  if (points_ == 0) return;
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, unsigned(Buf::ob_point), buffer_);
  place(contacts_, t);
  contacts_.run(points_);
}

}  // namespace maille::gpu
