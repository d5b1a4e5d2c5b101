// Stages that bound each point's motion within an explicit step: self-collision with
// primitive = "triangles" keeps every point's displacement within a share of its distance to
// the faces and edges it could reach, so that no triangle passes through another between two
// detections (docs/implicit.md, "Intersection-free cloth: what holds"). A stage implements it
// beside Stage (as obstacles implement PointContacts); the simulator asks every force stage that
// does, after an explicit scheme moved the points and before the step ends. Implicit schemes
// bound their own iterates (VBD's conservative bounds) and never call it.
#pragma once

#include <cstdint>

#include "maille/vec3.hpp"

namespace maille {

struct Model;
struct State;
class Profile;

class MotionBound {
 public:
  virtual ~MotionBound() = default;
  // After the scheme moved the points from x_n (the positions of the step's first force pass)
  // to s.x(): each bounded point whose displacement is longer than its bound is moved back
  // along it to the bound, and its velocity becomes the clamped displacement over h. Counters
  // into `profile`; returns the points clamped.
  virtual std::uint64_t bound_motion(const Model& m, State& s, Real h, Profile& profile) = 0;
};

}  // namespace maille
