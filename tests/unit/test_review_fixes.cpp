// Small things a code review found (issue 22), each with the test that keeps it fixed: one rule
// for duplicate names in every registry, the conditional link's Jacobian tied to its distance
// policy, one named "never" cadence.
#include <gtest/gtest.h>

#include "maille/backend.hpp"
#include "maille/integrator.hpp"
#include "maille/link_registry.hpp"
#include "maille/links/conditional.hpp"
#include "maille/links/spring.hpp"
#include "maille/scene.hpp"
#include "maille/stage_registry.hpp"

namespace {

using namespace maille;

TEST(ReviewFixes, EveryRegistryRefusesASecondEntryUnderOneName) {
  LinkKindRegistry kinds = LinkKindRegistry::with_builtins();
  EXPECT_THROW(kinds.add<Spring>(), std::logic_error);
  StageRegistry stages = StageRegistry::with_builtins();
  EXPECT_THROW(stages.add({"self_collision", false, "again", nullptr}), std::logic_error);
  IntegratorRegistry schemes;
  schemes.add({"mine", "a scheme", nullptr});
  EXPECT_THROW(schemes.add({"mine", "the same name", nullptr}), std::logic_error);
  BackendRegistry backends;
  backends.add({"cpu", "the reference", {}});
  try {
    backends.add({"cpu", "another", {}});
    FAIL() << "accepted";
  } catch (const std::logic_error& e) {
    EXPECT_STREQ(e.what(), "backend registry: 'cpu' is already registered");
  }
}

// A distance that is not Euclidean (the law acts along it, its Jacobian would differ): the kind
// has no Jacobian, so implicit Euler refuses it by name instead of using the Euclidean blocks.
struct ScaledDistance {
  static constexpr std::string_view keyword = "scaled_conditional";
  static Separation separation(const Vec3& xa, const Vec3& xb) {
    return maille::separation(xa, xb * Real(2));
  }
  static bool within(const Vec3& xa, const Vec3& xb, Real s) {
    return norm2(xb * Real(2) - xa) < s * s;
  }
};

TEST(ReviewFixes, TheConditionalJacobianExistsForTheEuclideanDistanceOnly) {
  EXPECT_TRUE(LinkPool<ConditionalSpringDamper>{}.has_jacobian());
  EXPECT_FALSE(LinkPool<ConditionalSpringDamperT<ScaledDistance>>{}.has_jacobian());
  Model m;
  m.points.add(PointKind::fixed, 1, {0, 0, 0});
  m.points.add(PointKind::free, 1, {0.1, 0, 0});
  m.links.pool<ConditionalSpringDamperT<ScaledDistance>>().add({0, 1}, {100, 0, 0.5, 0.5});
  const auto scheme = IntegratorRegistry::builtin().find("implicit_euler")->make({});
  EXPECT_NE(scheme->check(m).find("'scaled_conditional' provides no Jacobian"), std::string::npos)
      << scheme->check(m);
}

TEST(ReviewFixes, TheLargestCadenceIsTheNamedNever) {
  static const LinkKindRegistry kinds = LinkKindRegistry::with_builtins();
  const auto r = parse_scene(
      "[simulation]\noutput_every = 1073741825\n[[mass]]\nposition = [0, 0, 0]\n", "t.toml", kinds);
  ASSERT_FALSE(r);
  EXPECT_EQ(r.error().message,
            "must be in [1, " + std::to_string(kNeverEvery) + "] (got 1073741825)");
}

}  // namespace
