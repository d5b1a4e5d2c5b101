// Stages installed by scene tables: a stage defined only in this file ([test_anchor]: a linear
// spring pulling one point toward a fixed position, as a force stage) is registered, read from a
// scene with its own keys and errors, installed in every simulator of the model, and runs at its
// phase with the step context. Physics check: the point oscillates with omega = sqrt(k/m).
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "maille/links/spring_damper.hpp"
#include "maille/scene.hpp"
#include "test_support.hpp"

namespace {

using namespace maille;

struct AnchorConfig {
  std::uint32_t point = 0;
  Vec3 target{};
  Real stiffness = 0;
};

class AnchorStage final : public Stage {
 public:
  explicit AnchorStage(AnchorConfig c) : c_(c) {}
  std::string name() const override { return "test_anchor"; }
  Phase phase() const override { return Phase::forces; }
  void apply(const Model&, State& s, const StageContext& ctx) override {
    s.f()[c_.point] += (c_.target - s.x()[c_.point]) * c_.stiffness;
    last_h = ctx.h;
    last_velocity = ctx.velocity;
  }
  double last_h = 0;
  VelocityTime last_velocity = VelocityTime::synchronous;

 private:
  AnchorConfig c_;
};

// Counts its calls and checks it sees the positions after integration.
class AfterStage final : public Stage {
 public:
  explicit AfterStage(int* calls) : calls_(calls) {}
  std::string name() const override { return "test_after"; }
  Phase phase() const override { return Phase::after_integration; }
  void apply(const Model&, State& s, const StageContext& ctx) override {
    ++*calls_;
    EXPECT_DOUBLE_EQ(ctx.t, s.time);
  }

 private:
  int* calls_;
};

StageRegistry test_registry(int* after_calls) {
  StageRegistry r = StageRegistry::with_builtins();
  r.add({"test_anchor", false, "a spring from a point to a fixed position (test only)",
         [](SceneTable& t, const Model& m) {
           AnchorConfig c;
           const auto p = t.integer("point", 0, 0, std::int64_t(m.points.size()) - 1);
           c.point = static_cast<std::uint32_t>(p);
           c.target = t.vec3("target", {0, 0, 0});
           c.stiffness = t.real("stiffness", Bound::positive);
           return StageSpec{"test_anchor", Phase::forces,
                            [c](const Model&) { return std::make_unique<AnchorStage>(c); }};
         }});
  r.add({"test_after", true, "counts after-integration calls (test only)",
         [after_calls](SceneTable&, const Model&) {
           return StageSpec{"test_after", Phase::after_integration, [after_calls](const Model&) {
                              return std::make_unique<AfterStage>(after_calls);
                            }};
         }});
  return r;
}

// A 0.5 kg point 0.1 m from the origin, no gravity: the scenes below add their tables to it.
const std::string kBob = R"(
[simulation]
step = 1e-3
[fields]
gravity = [0.0, 0.0, 0.0]
[[mass]]
name = "bob"
mass = 0.5
position = [0.1, 0.0, 0.0]
)";

const std::string kScene = kBob + R"([test_anchor]
point = 0
stiffness = 50.0
[[test_after]]
[[test_after]]
)";

TEST(StageRegistry, SceneTableInstallsAStageThatRunsWithThePhysicsItDescribes) {
  int after_calls = 0;
  const StageRegistry stages = test_registry(&after_calls);
  auto scene = parse_scene(kScene, "anchor.toml", LinkKindRegistry::with_builtins(), stages);
  ASSERT_TRUE(scene) << scene.error().to_string();
  ASSERT_EQ(scene->model.stages.size(), 3u);
  Simulator sim(scene->model, test::settings(1e-3));
  // omega = sqrt(k / m) = 10 rad/s: a period of 2 pi / 10 s.
  const auto t = test::upward_crossings(sim, 0, 0, 5000);
  ASSERT_GE(t.size(), 3u);
  EXPECT_NEAR(test::mean_period(t), 2 * std::numbers::pi / 10,
              1e-4);                 // leapfrog: O(h^2) = 1e-6 rel
  EXPECT_EQ(after_calls, 2 * 5000);  // two [[test_after]] tables, every step
  bool timed = false;
  for (const auto& s : sim.profile().stages()) timed |= s.name == "test_anchor" && s.total_ns > 0;
  EXPECT_TRUE(timed);
}

TEST(StageRegistry, DisabledStagesAreNotInstalled) {
  int after_calls = 0;
  const StageRegistry stages = test_registry(&after_calls);
  auto scene = parse_scene(kScene, "anchor.toml", LinkKindRegistry::with_builtins(), stages);
  ASSERT_TRUE(scene);
  SimulationSettings s = test::settings(1e-3);
  s.disabled_stages = {"test_anchor", "test_after"};
  Simulator sim(scene->model, s);
  sim.run_steps(100);
  EXPECT_EQ(after_calls, 0);
  EXPECT_DOUBLE_EQ(sim.state().x()[0].x, 0.1);  // no force at all
}

TEST(StageRegistry, StageTableErrorsNameFileLineAndKey) {
  int after_calls = 0;
  const StageRegistry stages = test_registry(&after_calls);
  auto unknown = parse_scene(R"([[mass]]
mass = 1.0
position = [0.0, 0.0, 0.0]
[test_anchor]
stiffness = 1.0
colour = "red"
)",
                             "anchor.toml", LinkKindRegistry::with_builtins(), stages);
  ASSERT_FALSE(unknown);
  EXPECT_EQ(unknown.error().line, 6);
  EXPECT_NE(unknown.error().key.find("colour"), std::string::npos);
  auto negative = parse_scene(R"([[mass]]
mass = 1.0
position = [0.0, 0.0, 0.0]
[test_anchor]
stiffness = -1.0
)",
                              "anchor.toml", LinkKindRegistry::with_builtins(), stages);
  ASSERT_FALSE(negative);
  EXPECT_EQ(negative.error().line, 5);
  EXPECT_NE(negative.error().key.find("stiffness"), std::string::npos);
  // Without the registry entry the table is an unknown key.
  auto plain = parse_scene(kScene, "anchor.toml", LinkKindRegistry::with_builtins());
  EXPECT_FALSE(plain);
}

// A gathered table: every [[test_pull]] at once makes one stage (the sum of their springs from
// one point toward the origin), and a table with `link = true` also adds a spring-damper link
// to the model, as [[contact]] by links does. Two pulls of 20 and 30 N/m on a 0.5 kg point:
// one stage of 50 N/m, omega = 10 rad/s; with the second table's 30 N/m also as a link to a
// fixed point (0.1 m behind it, rest length 0.1 m: the same equilibrium), omega = sqrt(80 / 0.5).
StageRegistry pull_registry() {
  StageRegistry r = StageRegistry::with_builtins();
  StageTableEntry pull{
      "test_pull", true, "springs toward the origin, one stage (test only)", nullptr, {}};
  pull.gather = [](std::span<SceneTable* const> tables, Model& m) -> std::optional<StageSpec> {
    AnchorConfig c;
    for (SceneTable* t : tables) {
      c.stiffness += t->real("stiffness", Bound::positive);
      if (t->boolean("link", false)) {
        const std::uint32_t fixed = m.points.add(PointKind::fixed, 1, {-0.1, 0, 0});
        const SpringDamper::Params p{t->real("stiffness", Bound::positive), Real(0.1), 0};
        m.links.pool<SpringDamper>().add({0, fixed}, p);
      }
    }
    return StageSpec{"test_pulls", Phase::forces,
                     [c](const Model&) { return std::make_unique<AnchorStage>(c); }};
  };
  r.add(std::move(pull));
  return r;
}

TEST(StageRegistry, AGatheredTableMakesOneStageFromAllItsElements) {
  const std::string& head = kBob;
  auto omega = [&](const std::string& tables, std::size_t stages, std::size_t links) {
    auto scene =
        parse_scene(head + tables, "pull.toml", LinkKindRegistry::with_builtins(), pull_registry());
    EXPECT_TRUE(scene) << scene.error().to_string();
    if (!scene) return 0.0;
    EXPECT_EQ(scene->model.stages.size(), stages);
    EXPECT_EQ(scene->model.links.total(), links);
    Simulator sim(scene->model, test::settings(1e-4));
    const auto t = test::upward_crossings(sim, 0, 0, 20000);
    return t.size() >= 3 ? 2 * std::numbers::pi / test::mean_period(t) : 0.0;
  };
  // leapfrog at 1e-4 s: O((omega h)^2) = 1e-6 relative.
  EXPECT_NEAR(omega("[[test_pull]]\nstiffness = 20.0\n[[test_pull]]\nstiffness = 30.0\n", 1, 0), 10,
              1e-3);
  EXPECT_NEAR(
      omega("[[test_pull]]\nstiffness = 20.0\n[[test_pull]]\nstiffness = 30.0\nlink = true\n", 1,
            1),
      std::sqrt(80 / 0.5), 1e-2);
  // Each element's unknown keys are refused at their line, as for any table.
  auto bad = parse_scene(
      head + "[[test_pull]]\nstiffness = 20.0\n[[test_pull]]\nstiffness = 1.0\nstifnes = 2.0\n",
      "pull.toml", LinkKindRegistry::with_builtins(), pull_registry());
  ASSERT_FALSE(bad);
  EXPECT_EQ(bad.error().line, 14);  // kBob's 9 lines (the first empty), then the tables
  EXPECT_NE(bad.error().key.find("stifnes"), std::string::npos) << bad.error().to_string();
}

// [[contact]] is such a table: its `between` names groups, and one that names no group is blamed
// at its own item (line and column), not at the key.
TEST(StageRegistry, AContactNamingNoGroupIsBlamedAtTheItem) {
  auto scene = parse_scene(R"([[rope]]
name = "a"
start = [0.0, 0.0, 0.0]
end = [1.0, 0.0, 0.0]
points = 4
mass = 0.1
[[rope]]
name = "b"
start = [0.0, 1.0, 0.0]
end = [1.0, 1.0, 0.0]
points = 4
mass = 0.1
[[contact]]
between = ["a",
           "nope"]
)",
                           "contact.toml", LinkKindRegistry::with_builtins());
  ASSERT_FALSE(scene);
  EXPECT_EQ(scene.error().line, 15);
  EXPECT_EQ(scene.error().column, 12);
  EXPECT_NE(scene.error().to_string().find("no group named 'nope'"), std::string::npos);
}

// A stage that produces a NaN force is named in the blow-up report, before anything moves.
class NanStage final : public ForceStage {
 public:
  std::string name() const override { return "nan_maker"; }
  void apply(const Model&, State& s, const StageContext& ctx) override {
    if (ctx.step == 5) s.f()[1].y = std::nan("");
  }
};

TEST(StageRegistry, BlowUpInsideAStageIsNamed) {
  Simulator sim(test::oscillator(1, 100, 0, 1, 0.1), test::settings(1e-3));
  sim.add_stage(std::make_unique<NanStage>());
  EXPECT_FALSE(sim.run_steps(100));
  ASSERT_TRUE(sim.blow_up());
  EXPECT_EQ(sim.blow_up()->module, "nan_maker");
  EXPECT_EQ(sim.blow_up()->step, 5u);
  EXPECT_TRUE(std::isfinite(sim.state().x()[1].y));  // caught before integration
}

}  // namespace
