// Wall-clock intervals for what programs report (a run's summary, a sweep's cases, a study's
// timings): one helper. The engine's own stage timings are the Profile's (profile.hpp).
#pragma once

#include <chrono>

namespace maille {

using WallClock = std::chrono::steady_clock;

// Seconds from t0 to now.
inline double seconds_since(WallClock::time_point t0) {
  return std::chrono::duration<double>(WallClock::now() - t0).count();
}

}  // namespace maille
