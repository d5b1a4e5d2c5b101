// Internal to the `maille` commands: loading a scene with its errors printed, the step count of a
// duration, warnings on stderr (commands.cpp, render_command.cpp).
#pragma once

#include <cmath>
#include <cstdint>
#include <iostream>
#include <new>
#include <optional>
#include <string>
#include <vector>

#include "maille/limits.hpp"
#include "maille/scene.hpp"

namespace maille::app {

// What an interrupt says while a scene loads and its simulator is set up: nothing of the run is
// written yet and no loop polls, so it ends the process at once (exit 130), whatever step of
// the loading it is in (a long sampling, a large build). The commands that write files count
// interrupts instead once their simulator is built (interrupt::counted), so that an interrupt
// while frame 0 is written or during the run ends with complete files (and exit 130).
inline constexpr char kLoadingInterrupted[] =
    "interrupted while loading the scene: nothing written\n";

inline std::optional<Scene> load_or_report(const std::string& path,
                                           const std::vector<std::string>& sets = {}) {
  try {
    Result<Scene> r = load_scene(path, sets);
    if (!r) {
      std::cerr << r.error().to_string() << '\n';
      return std::nullopt;
    }
    return std::move(r.value());
  } catch (const std::bad_alloc&) {  // the size checks should make this unreachable
    std::cerr << path << ": error: out of memory while building the scene\n";
    return std::nullopt;
  }
}

#ifdef MAILLE_WITH_RENDER
// The number of steps a render of `duration` seconds takes, refused (usage error) above
// limits::max_steps: a run that cannot end is a mistake, not a request (SceneRun checks a run's).
inline std::optional<std::uint64_t> steps_for(double duration, double step, const char* what) {
  const double n = std::round(duration / step);
  if (!(n <= double(limits::max_steps))) {
    std::cerr << "error: " << what << " " << duration << " s at a step of " << step << " s is " << n
              << " steps, more than the limit of " << double(limits::max_steps) << '\n';
    return std::nullopt;
  }
  return static_cast<std::uint64_t>(n);
}
#endif

inline std::uint64_t points_of(const Model& m, PointKind k) {
  return m.points.count(k);
}

inline void print_warnings(const std::vector<std::string>& warnings) {
  for (const std::string& w : warnings) std::cerr << "warning: " << w << '\n';
}

}  // namespace maille::app
