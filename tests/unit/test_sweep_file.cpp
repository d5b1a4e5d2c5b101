// Sweep files (include/maille/sweep.hpp): axes in the file's order, cases numbered in the order
// of their product, values turned into --set text that reads back exactly, errors with the line
// and the key, and the axes' keys checked against the scene.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>

#include "maille/scene.hpp"
#include "maille/sweep.hpp"

namespace maille {
namespace {

const std::string kChain = std::string(MAILLE_SOURCE_DIR) + "/examples/pendulum_chain.toml";

std::filesystem::path write(const std::string& name, const std::string& text) {
  const auto dir = std::filesystem::temp_directory_path() / "maille_test_sweep_file";
  std::filesystem::create_directories(dir);
  const auto path = dir / name;
  std::ofstream(path) << text;
  return path;
}

TEST(sweep_file, CasesFollowTheAxesInTheFileOrder) {
  // toml++ sorts a table's keys: "z" would come before "a" if the file's order were lost.
  const auto path = write("order.toml", "scene = \"" + kChain + "\"\nduration = 0.5\n[axes]\n" +
                                            "\"simulation.step\" = [1e-4, 2.5e-4, 0.001]\n" +
                                            "\"rope[0].stiffness\" = [100, 2.0e3]\n");
  Result<Sweep> s = load_sweep(path);
  ASSERT_TRUE(s) << s.error().to_string();
  EXPECT_EQ(s->scene, std::filesystem::path(kChain));
  ASSERT_TRUE(s->duration);
  EXPECT_EQ(*s->duration, 0.5);
  EXPECT_FALSE(s->frames);
  ASSERT_EQ(s->axes.size(), 2u);
  EXPECT_EQ(s->axes[0].key, "simulation.step");
  EXPECT_EQ(s->axes[0].line, 4);
  EXPECT_EQ(s->axes[1].key, "rope[0].stiffness");
  ASSERT_EQ(s->case_count(), 6u);
  // The last axis varies fastest.
  EXPECT_EQ(s->overrides(0),
            (std::vector<std::string>{"simulation.step=1e-04", "rope[0].stiffness=100"}));
  EXPECT_EQ(s->overrides(1),
            (std::vector<std::string>{"simulation.step=1e-04", "rope[0].stiffness=2000.0"}));
  EXPECT_EQ(s->overrides(5),
            (std::vector<std::string>{"simulation.step=0.001", "rope[0].stiffness=2000.0"}));
  EXPECT_EQ(s->case_id(0), "0000");
  EXPECT_EQ(s->case_id(5), "0005");
  EXPECT_FALSE(check_sweep_keys(*s)) << check_sweep_keys(*s)->to_string();
}

TEST(sweep_file, ValuesReadBackExactly) {
  const auto path = write(
      "values.toml", "scene = \"" + kChain + "\"\n[axes]\n" +
                         "\"simulation.step\" = [0.1, 0.30000000000000004, 1e-300]\n" +
                         "\"fields.gravity\" = [[0.0, -9.81, 0.0], [0, -1.62, 0]]\n" +
                         "\"simulation.integrator\" = [\"rk4\"]\n" + "[output]\nframes = true\n");
  Result<Sweep> s = load_sweep(path);
  ASSERT_TRUE(s) << s.error().to_string();
  EXPECT_TRUE(s->frames);
  EXPECT_FALSE(s->duration);
  EXPECT_EQ(s->axes[0].values[0], "0.1");
  EXPECT_EQ(s->axes[0].values[1], "0.30000000000000004");
  EXPECT_EQ(s->axes[1].values[0], "[0.0, -9.81, 0.0]");
  EXPECT_EQ(s->axes[1].values[1], "[0, -1.62, 0]");
  EXPECT_EQ(s->axes[2].values[0], "\"rk4\"");
  EXPECT_EQ(s->axes[2].labels[0], "rk4");  // the summary shows the string itself
  // Each case's overrides go through load_scene as they would from --set.
  Result<Scene> scene = load_scene(s->scene, s->overrides(1 * 2 + 1));
  ASSERT_TRUE(scene) << scene.error().to_string();
  EXPECT_EQ(scene->settings.step, 0.30000000000000004);
  EXPECT_EQ(scene->model.fields.gravity.y, -1.62);
  EXPECT_EQ(scene->settings.integrator, "rk4");
}

TEST(sweep_file, IdsWidenPastTenThousandCases) {
  std::string values = "[";
  for (int i = 0; i < 101; ++i) values += (i ? ", " : "") + std::to_string(i + 1) + ".0";
  values += "]";
  const auto path = write("wide.toml", "scene = \"" + kChain + "\"\n[axes]\n" +
                                           "\"rope[0].stiffness\" = " + values + "\n" +
                                           "\"rope[0].damping\" = " + values + "\n");
  Result<Sweep> s = load_sweep(path);
  ASSERT_TRUE(s) << s.error().to_string();
  EXPECT_EQ(s->case_count(), 10201u);
  EXPECT_EQ(s->case_id(7), "00007");
  EXPECT_EQ(s->case_id(10200), "10200");
  EXPECT_EQ(s->coordinates(10200), (std::vector<std::size_t>{100, 100}));
}

TEST(sweep_file, ErrorsGiveTheLineAndTheKey) {
  const std::string scene = "scene = \"" + kChain + "\"\n";
  auto error_of = [](const std::string& name, const std::string& text) {
    Result<Sweep> s = load_sweep(write(name, text));
    EXPECT_FALSE(s) << name;
    return s ? InputError{} : s.error();
  };
  InputError e = error_of("empty.toml", scene + "[axes]\n\"rope[0].mass\" = []\n");
  EXPECT_EQ(e.line, 3);
  EXPECT_EQ(e.key, "axes.\"rope[0].mass\"");
  e = error_of("unknown.toml", scene + "frames = true\n[axes]\n\"rope[0].mass\" = [1.0]\n");
  EXPECT_EQ(e.line, 2);
  EXPECT_EQ(e.key, "frames");
  e = error_of("duration.toml", scene + "duration = \"long\"\n[axes]\n\"rope[0].mass\" = [1.0]\n");
  EXPECT_EQ(e.line, 2);
  EXPECT_EQ(e.key, "duration");
  e = error_of("noscene.toml", "[axes]\n\"rope[0].mass\" = [1.0]\n");
  EXPECT_EQ(e.key, "scene");
  e = error_of("syntax.toml", scene + "[axes]\n\"rope[0].mass\" = [1.0,\n");
  EXPECT_GE(e.line, 3);
  EXPECT_NE(e.message.find("TOML syntax"), std::string::npos);
  std::string big = "[";
  for (int i = 0; i < 1001; ++i) big += (i ? ", " : "") + std::to_string(i);
  big += "]";
  e = error_of("cases.toml", scene + "[axes]\n\"a.b\" = " + big + "\n\"a.c\" = " + big + "\n");
  EXPECT_NE(e.message.find("more than 1000000 cases"), std::string::npos) << e.to_string();
  EXPECT_EQ(e.line, 4);
}

TEST(sweep_file, KeysAreCheckedAgainstTheScene) {
  const std::string scene = "scene = \"" + kChain + "\"\n[axes]\n\"rope[0].damping\" = [0.1]\n";
  auto check = [](const std::string& name, const std::string& text) {
    Result<Sweep> s = load_sweep(write(name, text));
    EXPECT_TRUE(s) << s.error().to_string();
    return check_sweep_keys(*s);
  };
  auto e = check("typo.toml", scene + "\"rope[0].stifness\" = [1.0]\n");
  ASSERT_TRUE(e);
  EXPECT_EQ(e->line, 4);
  EXPECT_EQ(e->key, "axes.\"rope[0].stifness\"");
  EXPECT_NE(e->message.find("unknown key"), std::string::npos);
  e = check("index.toml", scene + "\"rope[1].stiffness\" = [1.0]\n");
  ASSERT_TRUE(e);
  EXPECT_NE(e->message.find("index out of range"), std::string::npos) << e->to_string();
  e = check("table.toml", scene + "\"ropes.stiffness\" = [1.0]\n");
  ASSERT_TRUE(e);
  EXPECT_NE(e->message.find("unknown key"), std::string::npos) << e->to_string();
  // A bad value is not the key's fault: its case fails alone.
  EXPECT_FALSE(check("value.toml", scene + "\"rope[0].stiffness\" = [-1.0, 10.0]\n"));
  // A table the scene lacks may be created, as with --set.
  EXPECT_FALSE(check("created.toml", scene + "\"self_collision.radius\" = [0.01]\n"));
  e = check("noscene.toml", "scene = \"missing.toml\"\n[axes]\n\"a.b\" = [1]\n");
  ASSERT_TRUE(e);
  EXPECT_EQ(e->key, "scene");
  EXPECT_EQ(e->line, 1);
}

}  // namespace
}  // namespace maille
