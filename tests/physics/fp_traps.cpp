// Every physics test runs with floating-point traps on: an invalid operation (0/0, inf - inf,
// sqrt of a negative), a division by zero or an overflow stops the test with SIGFPE at the
// instruction that did it, instead of a NaN surfacing steps later (Jolt runs its tests this way).
// Tests that blow up on purpose turn the traps off around the run with test::FpTrapsOff
// (test_support.hpp). OpenMP's worker threads are created by the main thread after this, and
// inherit its floating-point environment.
#include <fenv.h>
#include <gtest/gtest.h>

namespace {

class FpTraps : public ::testing::Environment {
 public:
  void SetUp() override {
    feclearexcept(FE_ALL_EXCEPT);
    feenableexcept(FE_INVALID | FE_DIVBYZERO | FE_OVERFLOW);
  }
  void TearDown() override { fedisableexcept(FE_ALL_EXCEPT); }
};

[[maybe_unused]] ::testing::Environment* const fp_traps =
    ::testing::AddGlobalTestEnvironment(new FpTraps);

}  // namespace
