// `--set KEY=VALUE`: overrides go through the scene's own validation; errors name the key and
// the override; array-of-table indices are checked.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "maille/scene.hpp"

namespace maille {
namespace {

const std::string kFlag = std::string(MAILLE_SOURCE_DIR) + "/examples/flag_in_wind.toml";

Result<Scene> with(std::vector<std::string> sets) {
  return load_scene(kFlag, sets);
}

TEST(Overrides, GoodKeysChangeTheScene) {
  auto s =
      with({"simulation.step=1e-4", "simulation.integrator=rk4", "fields.gravity=[0, -1.62, 0]",
            "flag[0].stiffness=800", "flag[0].resolution=[10, 8]"});
  ASSERT_TRUE(s) << s.error().to_string();
  EXPECT_DOUBLE_EQ(s->settings.step, 1e-4);
  EXPECT_EQ(s->settings.integrator, "rk4");
  EXPECT_DOUBLE_EQ(s->model.fields.gravity.y, -1.62);
  EXPECT_EQ(s->model.group("flag")->count, 80u);
  // Later overrides win; a bare word is a string.
  auto t = with({"simulation.integrator=rk4", "simulation.integrator=leapfrog"});
  ASSERT_TRUE(t);
  EXPECT_EQ(t->settings.integrator, "leapfrog");
}

TEST(Overrides, ATableCanBeAddedFromTheCommandLine) {
  auto s = with({"self_collision.broad_phase=brute", "self_collision.groups=[\"flag\"]"});
  ASSERT_TRUE(s) << s.error().to_string();
  ASSERT_EQ(s->model.stages.size(), 1u);
  EXPECT_EQ(s->model.stages[0].name, "self_collision");
}

TEST(Overrides, ErrorsNameTheKey) {
  auto unknown = with({"simulation.stepp=1e-4"});
  ASSERT_FALSE(unknown);
  EXPECT_NE(unknown.error().to_string().find("stepp"), std::string::npos)
      << unknown.error().to_string();
  auto type = with({"simulation.step=fast"});
  ASSERT_FALSE(type);
  EXPECT_NE(type.error().key.find("simulation.step"), std::string::npos)
      << type.error().to_string();
  auto range = with({"flag[0].mass=-1"});
  ASSERT_FALSE(range);
  EXPECT_NE(range.error().key.find("mass"), std::string::npos);
  auto index = with({"flag[3].stiffness=800"});
  ASSERT_FALSE(index);
  EXPECT_NE(index.error().to_string().find("index out of range"), std::string::npos);
  EXPECT_NE(index.error().to_string().find("--set flag[3].stiffness=800"), std::string::npos);
  auto no_array = with({"mass[0].mass=1"});
  ASSERT_FALSE(no_array);
  auto through_value = with({"simulation.step.x=1"});
  ASSERT_FALSE(through_value);
  EXPECT_NE(through_value.error().to_string().find("not a table"), std::string::npos);
  for (const char* bad : {"simulation.step", "=1", "a..b=1", "flag[x].mass=1", "flag[0]=1"}) {
    auto r = with({bad});
    EXPECT_FALSE(r) << bad;
  }
}

}  // namespace
}  // namespace maille
