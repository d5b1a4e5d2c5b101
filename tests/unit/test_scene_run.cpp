// Running a scene file (maille/scene_run.hpp), the settings a running simulator takes
// (maille/live_settings.hpp) and stats.csv's one list of columns (for_each_stats_column).
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <type_traits>

#include "maille/io.hpp"
#include "maille/live_settings.hpp"
#include "maille/scene_run.hpp"
#include "test_support.hpp"

namespace maille {
namespace {

const std::filesystem::path kChain =
    std::filesystem::path(MAILLE_SOURCE_DIR) / "examples" / "pendulum_chain.toml";

std::filesystem::path temp_dir(const std::string& name) {
  auto d = std::filesystem::temp_directory_path() / ("maille_test_scene_run_" + name);
  std::filesystem::remove_all(d);
  return d;
}

std::vector<std::string> lines_of(const std::filesystem::path& p) {
  std::ifstream in(p);
  std::vector<std::string> lines;
  for (std::string line; std::getline(in, line);) lines.push_back(line);
  return lines;
}

SceneRunOptions chain_run(const std::string& name, std::uint64_t steps) {
  SceneRunOptions o;
  o.scene = kChain;
  o.steps = steps;
  o.threads = 1;
  o.out = temp_dir(name);
  return o;
}

TEST(SceneRun, RunsTheSceneIntoItsFolder) {
  SceneRunOptions o = chain_run("ok", 250);
  o.checkpoint_every = 100;
  o.every = 50;
  SceneRun run(o);
  ASSERT_TRUE(run.load()) << run.report().error;
  EXPECT_EQ(run.steps(), 250u);
  EXPECT_EQ(run.settings().publish_every, 50);
  const SceneRunReport& r = run.run();
  EXPECT_EQ(r.exit, exit_code::ok) << r.error;
  EXPECT_TRUE(r.written);
  EXPECT_EQ(r.steps_run, 250u);
  EXPECT_EQ(r.steps_taken, 250u);
  EXPECT_EQ(r.frames, 6u);      // frame 0, then every 50 steps
  EXPECT_EQ(r.stats_rows, 5u);  // samples at steps 0, 50, ..., 200 (sample_every = every)
  ASSERT_TRUE(r.energies);
  EXPECT_TRUE(std::isfinite(r.energies->total()));
  EXPECT_EQ(lines_of(o.out / "stats.csv").size(), 6u);
  EXPECT_TRUE(std::filesystem::exists(o.out / "checkpoint.bin"));
  EXPECT_TRUE(std::filesystem::exists(o.out / "frame_000005.ply"));
}

TEST(SceneRun, ABadOverrideIsBadInputWithItsKeyAndNothingWritten) {
  SceneRunOptions o = chain_run("bad", 10);
  o.sets = {"rope[0].stiffness=-1"};
  SceneRun run(o);
  EXPECT_FALSE(run.load());
  EXPECT_EQ(run.report().exit, exit_code::bad_input);
  ASSERT_TRUE(run.report().input);
  EXPECT_EQ(run.report().input->key, "rope[0].stiffness");
  EXPECT_FALSE(std::filesystem::exists(o.out));
}

TEST(SceneRun, ARunThatCannotEndIsAUsageError) {
  SceneRunOptions o = chain_run("long", 0);
  o.steps.reset();
  o.duration = 1e30;
  o.duration_name = "--duration";
  SceneRun run(o);
  EXPECT_FALSE(run.load());
  EXPECT_EQ(run.report().exit, exit_code::usage);
  EXPECT_NE(run.report().error.find("--duration 1e+30 s"), std::string::npos) << run.report().error;
}

TEST(SceneRun, ABlowUpIsReportedWithTheFilesComplete) {
  test::FpTrapsOff traps;
  SceneRunOptions o = chain_run("blowup", 2000);
  o.scene = std::filesystem::path(MAILLE_TEST_DATA) / "unstable_spring.toml";
  SceneRun run(o);
  ASSERT_TRUE(run.load()) << run.report().error;
  const SceneRunReport& r = run.run();
  EXPECT_EQ(r.exit, exit_code::blow_up);
  ASSERT_TRUE(r.blow_up);
  EXPECT_EQ(r.error, "error: " + r.blow_up->message);
  EXPECT_FALSE(r.energies);
  EXPECT_FALSE(lines_of(o.out / "stats.csv").empty());  // the header at least
}

TEST(SceneRun, AStopBeforeTheLoopWritesNothing) {
  SceneRunOptions o = chain_run("stop_early", 100);
  SceneRun run(o);
  ASSERT_TRUE(run.load());
  SceneRunHooks hooks;
  bool loaded = false;
  hooks.loaded = [&] { loaded = true; };
  hooks.stop = [] { return true; };
  const SceneRunReport& r = run.run(hooks);
  EXPECT_TRUE(loaded);
  EXPECT_EQ(r.exit, exit_code::interrupted);
  EXPECT_FALSE(r.written);
  EXPECT_FALSE(std::filesystem::exists(o.out));
}

TEST(SceneRun, AStopDuringTheLoopEndsItWithCompleteFiles) {
  SceneRunOptions o = chain_run("stop_loop", 1000);
  SceneRun run(o);
  ASSERT_TRUE(run.load());
  SceneRunHooks hooks;
  int polls = 0;
  hooks.stop = [&] { return ++polls > 300; };
  std::uint64_t finished_at = 0;
  hooks.finish = [&](const Simulator& sim) { finished_at = sim.steps_taken(); };
  const SceneRunReport& r = run.run(hooks);
  EXPECT_EQ(r.exit, exit_code::interrupted);
  EXPECT_TRUE(r.written);
  EXPECT_TRUE(r.error.empty());
  EXPECT_GT(r.steps_taken, 0u);
  EXPECT_LT(r.steps_taken, 1000u);
  EXPECT_EQ(finished_at, r.steps_taken);
  EXPECT_EQ(lines_of(o.out / "stats.csv").size(), r.stats_rows + 1);
}

TEST(StatsColumns, TheWriterWritesTheOneList) {
  const auto dir = temp_dir("columns");
  std::filesystem::create_directories(dir);
  Simulator sim(test::oscillator(1, 100, 0.1, 1, 0.1), test::settings(1e-3));
  std::vector<std::string> names;
  std::vector<bool> integer;
  {
    StatsWriter stats(dir / "stats.csv");
    sim.on_sample([&](const EnergySample& e, const Profile& p) {
      stats.write(e, p);
      names.clear();
      integer.clear();
      for_each_stats_column(e, p, [&](std::string_view prefix, std::string_view name, auto v) {
        names.push_back(std::string(prefix) + std::string(name));
        integer.push_back(std::is_integral_v<decltype(v)>);
      });
    });
    sim.run_steps(20);
    stats.close();
  }
  std::string header;
  for (const auto& n : names) header += (header.empty() ? "" : ",") + n;
  EXPECT_EQ(lines_of(dir / "stats.csv").front(), header);
  ASSERT_GE(names.size(), 2 + kEnergyColumns);
  EXPECT_EQ(names[1], "step");
  EXPECT_TRUE(integer[1]);
  EXPECT_FALSE(integer[0]);
}

// Each [simulation] key a running simulator cannot take is named when it differs; the live
// ones are applied (the scheme's settings) or left to the program (the duration).
TEST(LiveSettings, FixedKeysAreNamedAndLiveOnesApplied) {
  const SimulationSettings base = test::settings(1e-3);
  auto changed = [&](auto edit) {
    SimulationSettings s = base;
    edit(s);
    return std::string(fixed_setting_changed(base, s));
  };
  EXPECT_EQ(changed([](SimulationSettings& s) { s.publish_every = 7; }), "output_every");
  EXPECT_EQ(changed([](SimulationSettings& s) { s.sample_every = 7; }), "sample_every");
  EXPECT_EQ(changed([](SimulationSettings& s) { s.threads = 3; }), "threads");
  EXPECT_EQ(changed([](SimulationSettings& s) { s.runaway_factor = 2; }), "runaway_factor");
  EXPECT_EQ(changed([](SimulationSettings& s) { s.backend = "gpu"; }), "backend");
  EXPECT_EQ(changed([](SimulationSettings& s) { s.backend_options.device = 1; }), "gpu_device");
  EXPECT_EQ(changed([](SimulationSettings& s) {
              s.step = 2e-3;
              s.integrator = "rk4";
              s.duration = 1;
              s.implicit.max_iterations = 3;
            }),
            "");
  EXPECT_EQ(live_setting_keys(),
            "simulation.step, simulation.integrator, simulation.implicit.*, simulation.duration");

  Simulator sim(test::oscillator(1, 100, 0.1, 1, 0.1), base);
  SimulationSettings wanted = base;
  wanted.step = 5e-4;
  wanted.integrator = "rk4";
  wanted.implicit.max_iterations = 3;
  apply_live_settings(sim, wanted);
  EXPECT_EQ(sim.settings().step, 5e-4);
  EXPECT_EQ(sim.settings().integrator, "rk4");
  EXPECT_EQ(sim.settings().implicit.max_iterations, 3);
}

}  // namespace
}  // namespace maille
