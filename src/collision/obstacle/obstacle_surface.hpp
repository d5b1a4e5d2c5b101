// How obstacle stages show themselves (Stage::surfaces): the obstacle's mesh, made once, placed
// at the snapshot's time, tinted by method so a comparison scene tells them apart.
#pragma once

#include <memory>
#include <vector>

#include "maille/obstacle.hpp"
#include "maille/snapshot.hpp"

namespace maille {

class ObstacleSurface {
 public:
  // The mesh to draw: the obstacle's own (facets, conditional) or its shape tessellated.
  ObstacleSurface(const Obstacle& o, std::shared_ptr<const TriMesh> mesh)
      : mesh_(std::move(mesh)), name_(obstacle_stage_name(o)), colour_(colour(o.method)) {}

  void add(const Obstacle& o, double t, std::vector<SurfaceInstance>& out) const {
    const shapes::Affine a = o.motion.at(o.place, t);
    out.push_back({name_, mesh_, a.direct, a.translation, colour_});
  }
  const std::shared_ptr<const TriMesh>& mesh() const { return mesh_; }

 private:
  static std::array<float, 4> colour(ObstacleMethod m) {
    switch (m) {
      case ObstacleMethod::geometric:
        return {0.45f, 0.55f, 0.75f, 0.5f};
      case ObstacleMethod::facets:
        return {0.75f, 0.62f, 0.45f, 0.5f};
      case ObstacleMethod::conditional:
        return {0.5f, 0.72f, 0.5f, 0.5f};
    }
    return {0.6f, 0.6f, 0.6f, 0.5f};
  }

  std::shared_ptr<const TriMesh> mesh_;
  std::string name_;
  std::array<float, 4> colour_;
};

}  // namespace maille
