// Dragging a particle with the mouse: a spring from the grabbed particle to the cursor's point
// in the scene, applied by the physics thread as a force stage between the field forces and the
// integration. The UI thread moves the target; the stage reads it, both under one mutex.
#pragma once

#include <cstdint>
#include <memory>
#include <mutex>
#include <optional>

#include "maille/simulator.hpp"

namespace maille::viewer {

struct DragTarget {
  std::uint32_t point = 0;  // grabbed particle (a free point)
  Vec3 target{};            // where the mouse holds it, m
  Real stiffness = 0;       // k, N/m, >= 0
  Real damping = 0;         // c, N.s/m, >= 0: damps the particle's own velocity
};

// Shared by the UI thread (grab, move, release) and the physics thread (the stage).
class DragState {
 public:
  void grab(const DragTarget& t);
  void move_to(const Vec3& target);
  void release();
  std::optional<DragTarget> current() const;

 private:
  mutable std::mutex mutex_;
  std::optional<DragTarget> drag_;
};

// F = k (target - x_i) - c v_i on the grabbed particle; nothing when none is grabbed.
class DragSpring final : public ForceStage {
 public:
  explicit DragSpring(std::shared_ptr<const DragState> state) : state_(std::move(state)) {}
  std::string name() const override { return "mouse_drag"; }
  void apply(const Model& m, State& s, const StageContext& ctx) override;

 private:
  std::shared_ptr<const DragState> state_;
};

// A spring that lifts the whole model's free mass against gravity with a few centimetres of
// stretch, softened when the grabbed particle alone would make the step unstable.
DragTarget default_drag(const Model& m, double step, std::uint32_t point, const Vec3& target);

}  // namespace maille::viewer
