// Trust under bad input: the stability estimate always terminates, sizes are refused before
// anything is allocated, only regular scene files of sane size are read, and cadences stop at the
// named "never".
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>

#include "maille/limits.hpp"
#include "maille/link_registry.hpp"
#include "maille/links/spring.hpp"
#include "maille/scene.hpp"
#include "maille/simulator.hpp"
#include "maille/stability.hpp"

namespace maille {
namespace {

constexpr double inf = std::numeric_limits<double>::infinity();

// Every scheme answers for every (omega^2, c), however absurd, and the answer is sane:
// 0 <= h, and explicit schemes give a finite step for a finite stiffness.
TEST(StableStep, TerminatesOnOverflowedAndDegenerateInputs) {
  const double values[] = {0, 1e-320, 1e-300, 1, 1e300, 1e308, inf, std::nan("")};
  for (const auto& e : IntegratorRegistry::builtin().entries()) {
    const auto scheme = e.make(ImplicitSettings{});
    for (double w2 : values)
      for (double c : values) {
        const Real h = scheme->stable_step(w2, c);
        EXPECT_TRUE(h >= 0) << e.name << " w2 " << w2 << " c " << c << " gave " << h;
      }
    // An overflowed omega^2 is a very stiff link: explicit schemes get a tiny positive step
    // (about 1e-150 s: representable in double only).
    if (sizeof(Real) == sizeof(double) && e.name != "implicit_euler" &&
        e.name != "explicit_euler") {
      const Real h = scheme->stable_step(inf, 0);
      EXPECT_GT(h, 0) << e.name;
      EXPECT_LT(h, 1e-140) << e.name;
    }
  }
  const auto implicit = IntegratorRegistry::builtin().find("implicit_euler")->make({});
  EXPECT_TRUE(std::isinf(implicit->stable_step(inf, inf)));
}

TEST(StableStep, UnchangedForOrdinaryLinks) {
  // Leapfrog on an undamped oscillator: h* = 2 / omega.
  const auto leapfrog = IntegratorRegistry::builtin().find("leapfrog")->make({});
  EXPECT_NEAR(leapfrog->stable_step(100, 0), 0.2, 1e-6);
}

// A 1e-320 kg mass built in code (the scene reader refuses it): the estimate terminates.
TEST(StableStep, EstimateTerminatesForADenormalMass) {
  Model m;
  m.fields.gravity = {0, 0, 0};
  const auto hook = m.points.add(PointKind::fixed, 1, {0, 0, 0});
  const auto bob = m.points.add(PointKind::free, Real(1e-320), {1, 0, 0});
  m.links.pool<Spring>().add({hook, bob}, {1, 1});
  const auto leapfrog = IntegratorRegistry::builtin().find("leapfrog")->make({});
  const StabilityEstimate est = estimate_stability(m, *leapfrog);
  EXPECT_TRUE(est.max_step >= 0 && est.max_step < 1e-100) << est.max_step;
}

TEST(Limits, SizeCheckNamesPointsLinksAndBytes) {
  EXPECT_EQ(limits::check_size({1000, 6000, 2000}), "");
  const std::string why = limits::check_size({10'000'000'000, 60'000'000'000, 0});
  EXPECT_NE(why.find("10000000000 points"), std::string::npos) << why;
  EXPECT_NE(why.find("60000000000 links"), std::string::npos) << why;
  EXPECT_NE(why.find("GiB"), std::string::npos) << why;
  // Within the point cap but beyond the memory budget.
  const std::string mem = limits::check_size({limits::max_points, limits::max_links, 0});
  EXPECT_NE(mem.find("memory budget"), std::string::npos) << mem;
}

TEST(Limits, MemoryBudgetIsAFractionOfPhysicalMemory) {
  EXPECT_GT(limits::memory_budget_bytes(), std::uint64_t{64} << 20);
}

std::filesystem::path temp_dir(const std::string& name) {
  auto d = std::filesystem::temp_directory_path() / ("maille_test_" + name);
  std::filesystem::remove_all(d);
  std::filesystem::create_directories(d);
  return d;
}

TEST(SceneFile, DirectoryIsNamedAsSuch) {
  const auto d = temp_dir("scene_dir");
  const Result<Scene> r = load_scene(d);
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.error().message.find("is a directory"), std::string::npos) << r.error().to_string();
}

TEST(SceneFile, DeviceIsRefusedWithoutReading) {
  const Result<Scene> r = load_scene("/dev/zero");
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.error().message.find("not a regular file"), std::string::npos)
      << r.error().to_string();
}

TEST(SceneFile, OversizedFileIsRefusedWithoutReading) {
  const auto file = temp_dir("scene_big") / "big.toml";
  { std::ofstream(file) << "# big\n"; }
  std::filesystem::resize_file(file, limits::max_scene_file_bytes + 1);  // sparse: no disk used
  const Result<Scene> r = load_scene(file);
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.error().message.find("limited to"), std::string::npos) << r.error().to_string();
}

// The cadences (output_every, sample_every) stop at kNeverEvery, the named "never": a larger
// value is refused with that bound in the message.
TEST(Limits, TheLargestCadenceIsTheNamedNever) {
  static const LinkKindRegistry kinds = LinkKindRegistry::with_builtins();
  const auto r = parse_scene(
      "[simulation]\noutput_every = 1073741825\n[[mass]]\nposition = [0, 0, 0]\n", "t.toml", kinds);
  ASSERT_FALSE(r);
  EXPECT_EQ(r.error().message,
            "must be in [1, " + std::to_string(kNeverEvery) + "] (got 1073741825)");
}

}  // namespace
}  // namespace maille
