// What stands between a step and a crash or a silent failure: a non-finite state never reaches a
// stage (stage_input_finite), a stop request abandons a long implicit step and puts its start
// back, keys a solver ignores are said, unconverged implicit steps are counted, and outputs
// never rename over a FIFO, a device or a link.
#include <gtest/gtest.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <string>

#include "maille/io.hpp"
#include "maille/scene.hpp"
#include "maille/simulator.hpp"
#include "maille/threads.hpp"

namespace maille {
namespace {

Scene example(const std::string& name, std::vector<std::string> sets = {}) {
  const auto path = std::filesystem::path(MAILLE_SOURCE_DIR) / "examples" / (name + ".toml");
  Result<Scene> r = load_scene(path, sets);
  if (!r) throw std::runtime_error(r.error().to_string());
  r.value().settings.threads = 1;
  return std::move(r.value());
}

Simulator simulator(const std::string& name, std::vector<std::string> sets = {}) {
  Scene s = example(name, std::move(sets));
  return Simulator(std::move(s.model), s.settings);
}

const std::vector<std::string> kLongVbd = {"simulation.integrator=implicit_euler",
                                           "simulation.step=0.05", "simulation.implicit.solver=vbd",
                                           "simulation.implicit.iterations=200"};
// At 0.1 s the cloth meets the sphere in its third step: Newton's iterations do not end early
// there (in free fall the second one is exact).
const std::vector<std::string> kLongCg = {
    "simulation.integrator=implicit_euler",   "simulation.step=0.1",
    "simulation.implicit.solver=matrix_free", "simulation.implicit.newton_iterations=2",
    "simulation.implicit.tolerance=1e-300",   "simulation.implicit.max_iterations=200"};

TEST(StageInput, ANonFinitePositionIsABlowUpBeforeAnyStageSeesIt) {
  for (const double bad : {std::numeric_limits<double>::infinity(), std::nan("")}) {
    Simulator sim = simulator("cloth_on_sphere");
    ASSERT_TRUE(sim.step());
    sim.state_for_editing().x()[40].y = Real(bad);
    EXPECT_FALSE(sim.step());
    ASSERT_TRUE(sim.blow_up());
    EXPECT_NE(sim.blow_up()->message.find("at point 40"), std::string::npos)
        << sim.blow_up()->message;
    EXPECT_NE(sim.blow_up()->message.find("before stage"), std::string::npos);
    EXPECT_FALSE(sim.blow_up()->module.empty());
  }
}

TEST(StageInput, ARestoredNonFiniteStateIsABlowUp) {
  Simulator sim = simulator("cloth_on_sphere", kLongVbd);
  State s = sim.state();
  s.v()[3].x = std::numeric_limits<Real>::infinity();  // as a checkpoint may hold
  sim.restore(std::move(s));
  EXPECT_FALSE(sim.step());
  ASSERT_TRUE(sim.blow_up());
  EXPECT_NE(sim.blow_up()->message.find("at point 3"), std::string::npos) << sim.blow_up()->message;
}

// Asked during the step, a stop makes the step leave the state as it found it, to the bit; the
// next step runs as if nothing had happened.
void expect_stop_inside_the_step(const std::vector<std::string>& sets, int before) {
  Simulator sim = simulator("cloth_on_sphere", sets);
  Simulator reference = simulator("cloth_on_sphere", sets);
  for (int k = 0; k < before; ++k) {
    ASSERT_TRUE(sim.step());
    ASSERT_TRUE(reference.step());
  }
  const std::uint64_t start = state_hash(sim.state());
  int polls = 0;
  sim.on_stop_request([&polls] { return ++polls >= 3; });
  EXPECT_FALSE(sim.step());
  EXPECT_TRUE(sim.interrupted());
  EXPECT_FALSE(sim.blow_up());
  EXPECT_EQ(polls, 3);  // asked inside the solve, not at its end
  EXPECT_EQ(state_hash(sim.state()), start);
  EXPECT_EQ(sim.steps_taken(), std::uint64_t(before));
  sim.on_stop_request([] { return false; });
  ASSERT_TRUE(sim.step()) << (sim.blow_up() ? sim.blow_up()->message : "no blow-up");
  EXPECT_FALSE(sim.interrupted());
  ASSERT_TRUE(reference.step());
  EXPECT_EQ(state_hash(sim.state()), state_hash(reference.state()));
}

TEST(StopRequest, AbandonsAVbdStepBetweenSweepsAndKeepsItsStart) {
  expect_stop_inside_the_step(kLongVbd, 1);
}

TEST(StopRequest, AbandonsAConjugateGradientStepAndKeepsItsStart) {
  expect_stop_inside_the_step(kLongCg, 2);
}

TEST(SchemeWarnings, KeysTheSolverDoesNotReadAreSaid) {
  Simulator vbd = simulator(
      "flag_in_wind", {"simulation.integrator=implicit_euler", "simulation.implicit.solver=vbd",
                       "simulation.implicit.tolerance=1e-9"});
  bool said = false;
  for (const auto& w : vbd.stage_warnings())
    said |= w.find("tolerance") != std::string::npos && w.find("vbd") != std::string::npos;
  EXPECT_TRUE(said);
  Simulator cg = simulator("flag_in_wind", {"simulation.integrator=implicit_euler",
                                            "simulation.implicit.solver=matrix_free",
                                            "simulation.implicit.tolerance=1e-9"});
  for (const auto& w : cg.stage_warnings()) EXPECT_EQ(w.find("tolerance"), std::string::npos) << w;
  Simulator explicit_run = simulator("flag_in_wind", {"simulation.implicit.iterations=20"});
  said = false;
  for (const auto& w : explicit_run.stage_warnings())
    said |= w.find("iterations") != std::string::npos && w.find("leapfrog") != std::string::npos;
  EXPECT_TRUE(said);
}

// matrix_free at h = 0.1 s on the cloth falling on the sphere: a linearised step far from the
// solution (415 J of elastic energy where 0.05 s leaves 0.02 J). At 1/60 s it converges.
TEST(Unconverged, ALargeLinearisedStepIsCounted) {
  Simulator coarse = simulator("cloth_on_sphere",
                               {"simulation.integrator=implicit_euler",
                                "simulation.implicit.solver=matrix_free", "simulation.step=0.1"});
  for (int k = 0; k < 8 && coarse.step(); ++k) {
  }
  ASSERT_TRUE(coarse.unconverged());
  EXPECT_GT(coarse.unconverged()->worst, Simulator::kUnconvergedResidual);
  EXPECT_NE(unconverged_text(coarse).find("matrix_free"), std::string::npos);
  Simulator fine = simulator(
      "cloth_on_sphere", {"simulation.integrator=implicit_euler", "simulation.implicit.solver=vbd",
                          "simulation.step=0.0166666666666667"});
  for (int k = 0; k < 30 && fine.step(); ++k) {
  }
  EXPECT_FALSE(fine.unconverged()) << unconverged_text(fine);
}

TEST(Threads, OneThreadOnlyInAChildForkedAfterTeams) {
  EXPECT_EQ(threads_startable(2), "");
  note_teams(2);
  EXPECT_EQ(usable_threads(4), 4);
  const pid_t child = fork();
  if (child == 0) _exit(usable_threads(4) == 1 && forked_after_teams() ? 0 : 1);
  int status = 0;
  ASSERT_EQ(waitpid(child, &status, 0), child);
  EXPECT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0);
  EXPECT_FALSE(forked_after_teams());
}

class OutputTargets : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ =
        std::filesystem::temp_directory_path() / ("maille_outputs_" + std::to_string(::getpid()));
    std::filesystem::remove_all(dir_);
    std::filesystem::create_directories(dir_);
  }
  void TearDown() override { std::filesystem::remove_all(dir_); }
  std::filesystem::path dir_;
};

TEST_F(OutputTargets, RegularFilesAreReplacedAndNodesWrittenInPlace) {
  EXPECT_FALSE(output_target(dir_ / "new.csv").direct);
  std::ofstream(dir_ / "old.csv") << "x";
  EXPECT_FALSE(output_target(dir_ / "old.csv").direct);
  ASSERT_EQ(::mkfifo((dir_ / "fifo").c_str(), 0600), 0);
  EXPECT_TRUE(output_target(dir_ / "fifo").direct);
  EXPECT_TRUE(output_target("/dev/null").direct);
  EXPECT_THROW(output_target(dir_), std::runtime_error);
  std::filesystem::create_symlink(dir_ / "old.csv", dir_ / "link.csv");
  const OutputTarget through = output_target(dir_ / "link.csv");
  EXPECT_EQ(through.file, std::filesystem::canonical(dir_ / "old.csv"));
  std::filesystem::create_symlink(dir_ / "nothing", dir_ / "dangling.csv");
  EXPECT_THROW(output_target(dir_ / "dangling.csv"), std::runtime_error);
}

TEST_F(OutputTargets, AnAtomicFileIntoDevNullLeavesTheDevice) {
  struct stat before {};
  ASSERT_EQ(::stat("/dev/null", &before), 0);
  {
    AtomicFile f("/dev/null");
    f.stream() << "bytes that go nowhere\n";
    f.commit();
  }
  struct stat after {};
  ASSERT_EQ(::stat("/dev/null", &after), 0);
  EXPECT_TRUE(S_ISCHR(after.st_mode));
  EXPECT_EQ(after.st_rdev, before.st_rdev);
  EXPECT_FALSE(std::filesystem::exists("/dev/null.tmp"));
}

TEST_F(OutputTargets, AnAtomicFileThroughALinkKeepsTheLink) {
  std::ofstream(dir_ / "target.txt") << "old";
  std::filesystem::create_symlink(dir_ / "target.txt", dir_ / "link.txt");
  {
    AtomicFile f(dir_ / "link.txt");
    f.stream() << "new";
    f.commit();
  }
  EXPECT_TRUE(std::filesystem::is_symlink(dir_ / "link.txt"));
  std::ifstream in(dir_ / "target.txt");
  std::string text;
  in >> text;
  EXPECT_EQ(text, "new");
}

}  // namespace
}  // namespace maille
