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
#include <string>
#include <vector>

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

// The implicit solvers at a large step (1/60 s), on examples with every kind of contact: a
// geometric obstacle and point-triangle self-collision (cloth_on_sphere, two_cloths),
// point-point self-collision (cloth_heap), [[contact]] as stored links and by the broad phase
// (lattice_balls_collide). Each case runs one second on one thread and on two: a solver's
// colours are updated in parallel without atomics and the contact lists are merged in thread
// order, so both give the same bits, and one hash file per case (tests/golden/implicit/) holds
// them.
struct ImplicitCase {
  const char* name;                // the hash file's name
  const char* example;             // examples/NAME.toml
  const char* solver;              // vbd or matrix_free
  std::vector<std::string> extra;  // more --set overrides
};

std::vector<ImplicitCase> implicit_cases() {
  std::vector<ImplicitCase> out;
  for (const char* solver : {"vbd", "matrix_free"}) {
    const std::string s = solver;
    out.push_back({"cloth_on_sphere", "cloth_on_sphere", solver, {}});
    out.push_back({"two_cloths", "two_cloths", solver, {}});
    out.push_back({"cloth_heap", "cloth_heap", solver, {}});
    out.push_back({"lattice_balls_links", "lattice_balls_collide", solver, {}});
    out.push_back({"lattice_balls_broad_phase",
                   "lattice_balls_collide",
                   solver,
                   {"contact[0].method=broad_phase"}});
  }
  return out;
}

struct ImplicitParam {
  ImplicitCase c;
  int threads;
};

std::vector<ImplicitParam> implicit_params() {
  std::vector<ImplicitParam> out;
  for (const auto& c : implicit_cases())
    for (int threads : {1, 2}) out.push_back({c, threads});
  return out;
}

// ctest's names show the case, not the parameter's bytes.
void PrintTo(const ImplicitParam& p, std::ostream* os) {
  *os << p.c.name << ' ' << p.c.solver << ", " << p.threads << " thread(s)";
}

class ImplicitGoldenHash : public ::testing::TestWithParam<ImplicitParam> {};

TEST_P(ImplicitGoldenHash, golden) {
  const auto& [c, threads] = GetParam();
  const std::string id = std::string(c.name) + "_" + c.solver;
  std::vector<std::string> overrides = {"simulation.integrator=implicit_euler",
                                        "simulation.step=0.016666666666666666",
                                        std::string("simulation.implicit.solver=") + c.solver};
  overrides.insert(overrides.end(), c.extra.begin(), c.extra.end());
  auto scene = load_scene(
      std::filesystem::path(MAILLE_SOURCE_DIR "/examples") / (std::string(c.example) + ".toml"),
      overrides);
  ASSERT_TRUE(scene.ok()) << scene.error().to_string();
  scene->settings.backend = "cpu";
  scene->settings.threads = threads;
  Simulator sim(std::move(scene->model), scene->settings);
  ASSERT_TRUE(sim.run_steps(60)) << sim.blow_up()->message;
  const std::string line = "60 steps " + hex(state_hash(sim.state()));

  const std::filesystem::path file =
      std::filesystem::path(MAILLE_SOURCE_DIR "/tests/golden/implicit") / (id + ".hash");
  if (const char* update = std::getenv("MAILLE_UPDATE_GOLDEN"); update && *update == '1') {
    if (threads == 1) {
      std::filesystem::create_directories(file.parent_path());
      std::ofstream(file) << line << '\n';
      GTEST_SKIP() << "recorded " << file << ": " << line;
    }
  }
  std::ifstream in(file);
  std::string expected;
  ASSERT_TRUE(std::getline(in, expected))
      << "no golden hash in " << file << "; record it with MAILLE_UPDATE_GOLDEN=1 ctest -R golden";
  EXPECT_EQ(line, expected) << id << " on " << threads
                            << " thread(s): the trajectory changed (or differs between thread "
                               "counts). If intended, record with MAILLE_UPDATE_GOLDEN=1 ctest "
                               "--test-dir build/dev -R golden and commit tests/golden/implicit/";
}

INSTANTIATE_TEST_SUITE_P(Implicit, ImplicitGoldenHash, ::testing::ValuesIn(implicit_params()),
                         [](const auto& p) {
                           return std::string(p.param.c.name) + "_" + p.param.c.solver + "_t" +
                                  std::to_string(p.param.threads);
                         });

}  // namespace
}  // namespace maille
