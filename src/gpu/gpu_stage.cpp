// The GPU's stage versions, registered in one place (gpu_stage.hpp).
#include "gpu_stage.hpp"

#include <stdexcept>

#include "gpu_obstacle.hpp"
#include "gpu_self_collision.hpp"
#include "maille/self_collision.hpp"

namespace maille::gpu {

void GpuStageRegistry::add(GpuStageEntry e) {
  if (find(e.stage)) registered_twice("GPU stage registry", e.stage);
  entries_.push_back(std::move(e));
}

const GpuStageEntry* GpuStageRegistry::find(std::string_view stage) const {
  for (const auto& e : entries_)
    if (e.stage == stage) return &e;
  for (const auto& e : entries_)
    if (e.stage.ends_with(':') && stage.starts_with(e.stage)) return &e;
  return nullptr;
}

const GpuStageRegistry& GpuStageRegistry::builtin() {
  static const GpuStageRegistry registry = [] {
    GpuStageRegistry r;
    r.add({std::string(kSelfCollisionStage.name), GpuSelfCollision::check,
           [](const Model& m, const Stage& st, const GpuLimits& limits) {
             return std::make_unique<GpuSelfCollision>(m, st, limits.max_invocations);
           }});
    r.add({std::string(kGpuObstacleFamily), GpuGeometricObstacle::check,
           [](const Model&, const Stage& st, const GpuLimits&) {
             return std::make_unique<GpuGeometricObstacle>(st);
           }});
    return r;
  }();
  return registry;
}

}  // namespace maille::gpu
