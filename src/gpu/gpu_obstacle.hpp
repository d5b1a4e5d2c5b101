// The geometric obstacle stage ([[obstacle]] method = "geometric") on the GPU: one dispatch per
// obstacle and step over its colliding points, adding the CPU stage's contact
// (include/maille/detail/obstacle_laws.glsl: the canonical distance, the penalty and its damper,
// Coulomb friction against the velocity relative to the moving surface) into f.
//
// Per step the host places the obstacle at t as the CPU does (ObstacleMotion::at, in double,
// rounded to float for the kernel's uniforms) and passes the surface's velocity field as a twist
// (ObstacleMotion::twist); the kernel culls points beyond the CPU's bounding sphere (grown by
// 2^-10, so that float rounding never culls a point the CPU keeps), then calls the shared law.
// Each point writes only its own force: no atomics, and obstacles run one after the other in
// the stages' order, as on the CPU.
//
// Refused (check): the other methods of [[obstacle]] (facets, conditional), by name.
// Not published: the CPU stage's counters obstacle_NAME_contacts and obstacle_NAME_depth (the
// backend publishes no stage's counters: reading them back would wait for the device every
// step).
#pragma once

#include <cstdint>
#include <string>
#include <string_view>

#include "gpu_layout.hpp"
#include "gpu_stage.hpp"
#include "kernel.hpp"
#include "maille/obstacle.hpp"
#include "maille/stage.hpp"

namespace maille::gpu {

// The registry's family entry: every [[obstacle]]'s stage is named by obstacle_stage_name.
inline constexpr std::string_view kGpuObstacleFamily = kObstacleStagePrefix;

class GpuGeometricObstacle final : public GpuStage {
 public:
  // Why the obstacle stage `st` has no GPU version: "" when it runs (method = "geometric").
  static std::string check(const Stage& st);

  explicit GpuGeometricObstacle(const Stage& st);  // the context must be current
  ~GpuGeometricObstacle() override;
  GpuGeometricObstacle(const GpuGeometricObstacle&) = delete;
  GpuGeometricObstacle& operator=(const GpuGeometricObstacle&) = delete;

  // Adds the contacts at the device's x and v, the obstacle placed at t, into f.
  void evaluate(double t) override;

 private:
  // The obstacle's placement, surface velocity and law's parameters at t, into `k`'s uniforms.
  void place(Kernel& k, double t) const;

  const Obstacle* obstacle_;
  std::uint32_t points_ = 0;
  float reach2_ = 0;     // m^2, the cull (+inf: none)
  unsigned buffer_ = 0;  // ob_point
  Kernel contacts_;
};

// The kernel's source (gpu_obstacle_shaders.cpp): per colliding point, the shared contact law
// into f.
std::string obstacle_contacts_shader();

}  // namespace maille::gpu
