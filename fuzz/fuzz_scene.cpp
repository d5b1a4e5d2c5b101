// libFuzzer target: scene text -> parse_scene -> Simulator, exactly what `maille validate` does.
// A bad scene must come back as an InputError, or as std::invalid_argument from the Simulator
// (a model it refuses); anything else (a crash, a sanitizer report, another exception) is a bug.
// Build: cmake --preset fuzz && cmake --build --preset fuzz; run: scripts/fuzz.sh [--quick].
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <stdexcept>
#include <string>
#include <string_view>

#include "maille/scene.hpp"
#include "maille/simulator.hpp"

// The work a stage does when it is built is bounded by the memory budget (limits.hpp): a
// conditional obstacle at a fine threshold samples millions of points, seconds under ASan, and
// a budget of 32 MiB refuses it (at reading, with the threshold that would fit) as a user's
// budget refuses larger ones. The fuzzer's time goes to the reader, not to valid big work. A
// budget set in the environment is kept.
extern "C" int LLVMFuzzerInitialize(int*, char***) {
  setenv("MAILLE_MEMORY_BUDGET", "33554432", 0);
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static const maille::LinkKindRegistry kinds = maille::LinkKindRegistry::with_builtins();
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  auto scene = maille::parse_scene(text, "fuzz.toml", kinds);
  if (!scene) return 0;
  // Large valid models (an example's 250k floor contacts) take seconds to prepare under ASan and
  // coverage: their simulation is the tests' business; the reader and builders ran already.
  constexpr std::size_t kFuzzBudget = 20'000;
  if (scene->model.points.size() + scene->model.links.total() > kFuzzBudget) return 0;
  try {
    maille::Simulator sim(std::move(scene->model), scene->settings);
  } catch (const std::invalid_argument&) {
  }
  return 0;
}
