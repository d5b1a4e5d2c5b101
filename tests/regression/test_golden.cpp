// Golden state hashes: each example, a fixed number of steps on one thread on the CPU, hashed
// (state_hash: positions, velocities, time, step, the scheme's history, the stages' memory) and
// compared with tests/golden/NAME.hash. A change of any bit of any example's trajectory fails
// here, by name; a change made on purpose is recorded with
//
//   MAILLE_UPDATE_GOLDEN=1 ctest --test-dir build/dev -R golden
//
// and the new files committed with it (docs/testing.md, "Golden state hashes", says which
// builds share them).
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "maille/scene.hpp"

namespace maille {
namespace {

std::vector<std::filesystem::path> examples() {
  std::vector<std::filesystem::path> out;
  for (const auto& e : std::filesystem::directory_iterator(MAILLE_SOURCE_DIR "/examples"))
    if (e.path().extension() == ".toml") out.push_back(e.path());
  std::sort(out.begin(), out.end());
  return out;
}

// A few hundred steps, fewer for large scenes: about 2e6 particle-steps at most (all examples
// together take seconds), at least 20 steps.
std::uint64_t steps_for(std::size_t points) {
  return std::clamp<std::uint64_t>(2'000'000 / std::max<std::size_t>(points, 1), 20, 300);
}

std::string hex(std::uint64_t h) {
  char s[17];
  std::snprintf(s, sizeof s, "%016llx", static_cast<unsigned long long>(h));
  return s;
}

class GoldenHash : public ::testing::TestWithParam<std::filesystem::path> {};

TEST_P(GoldenHash, golden) {
  const std::string name = GetParam().stem().string();
  auto scene = load_scene(GetParam());
  ASSERT_TRUE(scene.ok()) << scene.error().to_string();
  scene->settings.backend = "cpu";
  scene->settings.threads = 1;
  Simulator sim(std::move(scene->model), scene->settings);
  const std::uint64_t steps = steps_for(sim.model().points.size());
  ASSERT_TRUE(sim.run_steps(steps)) << sim.blow_up()->message;
  std::ostringstream line;
  line << steps << " steps " << hex(state_hash(sim.state()));

  const std::filesystem::path file =
      std::filesystem::path(MAILLE_SOURCE_DIR "/tests/golden") / (name + ".hash");
  if (const char* update = std::getenv("MAILLE_UPDATE_GOLDEN"); update && *update == '1') {
    std::ofstream(file) << line.str() << '\n';
    GTEST_SKIP() << "recorded " << file << ": " << line.str();
  }
  std::ifstream in(file);
  std::string expected;
  ASSERT_TRUE(std::getline(in, expected))
      << "no golden hash in " << file << "; record it with MAILLE_UPDATE_GOLDEN=1 ctest -R golden";
  EXPECT_EQ(line.str(), expected)
      << name << ": the trajectory changed. If that is intended, record the new hashes with "
      << "MAILLE_UPDATE_GOLDEN=1 ctest --test-dir build/dev -R golden and commit tests/golden/";
}

INSTANTIATE_TEST_SUITE_P(Examples, GoldenHash, ::testing::ValuesIn(examples()),
                         [](const auto& p) { return p.param.stem().string(); });

}  // namespace
}  // namespace maille
