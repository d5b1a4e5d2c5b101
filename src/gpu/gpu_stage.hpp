// The GPU seam for stages. A CPU stage (stage.hpp) runs on the GPU backend when a device version
// of it is registered here: one entry, like the CPU's StageRegistry, with
//   check     why this stage, as configured now (its live options too), cannot run on the
//             device: an option the device version does not honour is refused by name, never
//             ignored (empty: it runs);
//   make      its buffers and kernels, for the model and the stage (the context is current);
//   evaluate  (GpuStage) its dispatch at time t, at the stage's phase: Phase::forces versions
//             add into f after the forces kernel.
// An entry names one stage ("self_collision") or a family of stages by the prefix of their
// names, ending with ':' ("obstacle:" for every [[obstacle]]; its check refuses the members it
// does not run). The backend's explicit step finds stages through the registry alone: it
// refuses a stage with no entry (naming it, with the stage's own refusal_hint()) and runs the
// ones it made in order. Implicit Euler by VBD takes geometric obstacles itself
// (GeometricObstacleView, gpu_vbd_obstacles.hpp) and refuses every other stage (vbd_refuses,
// gpu_vbd.cpp).
//
// Adding a GPU stage: a GpuStage subclass and one add() line in gpu_stage.cpp.
#pragma once

#include <functional>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "maille/model.hpp"
#include "maille/stage.hpp"

namespace maille::gpu {

// What one dispatch reaches on this device (stages size their per-cell passes by it).
struct GpuLimits {
  double max_invocations = 0;
};

class GpuStage {
 public:
  virtual ~GpuStage() = default;
  // Runs the stage on the device state at time t (the step's buffers bound). Reads the CPU
  // stage's live options each time (the viewer switches them between steps).
  virtual void evaluate(double t) = 0;
};

struct GpuStageEntry {
  std::string stage;  // the CPU stage's name() it runs, or a family's prefix ending with ':'
  std::function<std::string(const Stage&)> check;
  std::function<std::unique_ptr<GpuStage>(const Model&, const Stage&, const GpuLimits&)> make;
};

class GpuStageRegistry {
 public:
  // The engine's one registry rule (names.hpp: registered_twice): a second entry under a name
  // throws std::logic_error.
  void add(GpuStageEntry e);
  // The entry for a stage's name: its own, else the family whose prefix it starts with.
  const GpuStageEntry* find(std::string_view stage) const;
  const std::vector<GpuStageEntry>& entries() const { return entries_; }
  // The device versions the engine ships (self-collision, geometric obstacles).
  static const GpuStageRegistry& builtin();

 private:
  std::vector<GpuStageEntry> entries_;
};

}  // namespace maille::gpu
