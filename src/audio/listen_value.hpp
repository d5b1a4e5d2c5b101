// The value a listener reads during a step's force pass (docs/sound.md "What a sample is"):
// shared by the Recorder (`maille run --audio`) and the LiveSource (`maille play`), so that the
// two hear exactly the same samples.
#pragma once

#include "maille/audio.hpp"
#include "maille/model.hpp"
#include "maille/stage.hpp"
#include "maille/state.hpp"

namespace maille::audio {

// `origin`: the point's initial position (position is measured from it).
inline double listened_value(const Listener& l, const Vec3& origin, const Model& m,
                             const State& s, const StageContext& ctx) {
  switch (l.quantity) {
    case Quantity::position:
      return dot(s.x()[l.point] - origin, l.axis);
    case Quantity::velocity: {
      Vec3 v = s.v()[l.point];
      // Leapfrog's v(n - 1/2) synchronised to t_n with the step's own forces.
      if (ctx.velocity == VelocityTime::half_step)
        v += s.f()[l.point] * (m.points.inv_mass[l.point] * Real(0.5 * ctx.h));
      return dot(v, l.axis);
    }
    case Quantity::force:
      return dot(s.f()[l.point], l.axis);
  }
  return 0;
}

}  // namespace maille::audio
