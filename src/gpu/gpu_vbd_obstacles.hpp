// Geometric obstacles inside the GPU's vertex block descent (gpu_vbd.hpp): the CPU solver's
// point contacts (src/integrators/implicit_vbd.cpp with GeometricObstacleStage's PointContacts)
// on the device. The obstacles' records (placed at t and at t + h), which of them collide with
// each point, their lagged friction per point and each point's touching flag live in the
// buffers vbd_obstacles ... vbd_touch (gpu_layout.hpp); the kernels' functions
// (vbd_obstacle_functions) follow the CPU solver step by step:
//   lag          per point at the step's start (x_n, v_n, placed at t): each obstacle's normal
//                force (0 out of contact) and normal, held for the solve (friction only)
//   terms        per point at an iterate, placed at t + h: the shared law's force, with the
//                held friction, into g; its block (k + z/h) n n^T + friction's into H; whether
//                the point touches (depth > 0). Points beyond an obstacle's cull sphere are
//                skipped unless they hold a friction force, as on the CPU
//   push         an obstacle's elastic force at rest: a touching point's Newton step that
//                moves against it does not leave the contact whole
//   leaves cleanly, the bisection of a step that starts or leaves a contact (10 halvings: it
//                stops just inside), the acceleration skipping touching points and jumps over
//                half the thinnest obstacle, and the continuous test of the guess and the
//                result (first touch along x_n -> x for points moving more than half the
//                thinnest obstacle): the CPU's rules
// At most kVbdMaxObstacles obstacles (bits of a word per point): more are refused by name.
#pragma once

#include <array>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "../integrators/implicit_vbd.hpp"  // the contact rules' kVbdBisections, kVbdMaxSegmentSamples
#include "gpu_layout.hpp"
#include "maille/model.hpp"
#include "maille/obstacle.hpp"
#include "maille/stage.hpp"

namespace maille::gpu {

inline constexpr std::uint32_t kVbdMaxObstacles = 32;

// The geometric obstacles among `stages` (their GPU's VBD takes them inside the solve).
std::uint32_t vbd_obstacle_count(std::span<const Stage* const> stages);

class GpuVbdObstacles {
 public:
  GpuVbdObstacles();  // the context must be current
  ~GpuVbdObstacles();
  GpuVbdObstacles(const GpuVbdObstacles&) = delete;
  GpuVbdObstacles& operator=(const GpuVbdObstacles&) = delete;
  void forget() { forgotten_ = true; }  // the context is gone: nothing to delete

  // The geometric obstacles among `stages`, in their order, for the model's points.
  void load(const Model& m, std::span<const Stage* const> stages);
  std::uint32_t count() const { return std::uint32_t(obstacles_.size()); }
  // The thinnest obstacle's thickness, m (+inf: none, or planes only), as the CPU's thinnest_.
  float thinnest() const { return thinnest_; }
  // Records [0, count) placed at t, [count, 2 count) at t_next.
  void place(double t, double t_next);
  void bind() const;

 private:
  struct Entry {
    const Obstacle* obstacle;
    Real reach;
  };
  std::vector<Entry> obstacles_;
  float thinnest_ = 0;
  std::vector<ObstacleRecord> records_;
  std::array<unsigned, 4> buffers_{};  // vbd_obstacles, vbd_ob_member, vbd_ob_lag, vbd_touch
  bool forgotten_ = false;
};

// GLSL: the functions above (uniforms u_obstacles, u_placed, u_thinnest; the buffers
// vbd_obstacles ... vbd_touch and vbd_xn declared), after the kernel head.
std::string vbd_obstacle_functions();

}  // namespace maille::gpu
