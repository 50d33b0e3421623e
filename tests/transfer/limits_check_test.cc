// The runner's limits against the bench's announced limits (limits_check.h).
#include "hybridtest/transfer/limits_check.h"

#include <gtest/gtest.h>

#include "hybridtest/common/error.h"

namespace hybridtest::transfer {
namespace {

std::string ErrorOf(const SafetyLimits& runner, const SafetyLimits& bench) {
  try {
    CheckLimitsAgainstBench(runner, bench, "substructures.r1.safety", "the bench at h:1");
  } catch (const ConfigError& e) {
    return e.what();
  }
  return {};
}

TEST(LimitsCheck, EqualOrNarrowerLimitsPass) {
  const SafetyLimits bench;
  EXPECT_EQ(ErrorOf(bench, bench), "");
  SafetyLimits narrow = bench;
  narrow.stroke_min = -0.1;
  narrow.stroke_max = 0.1;
  narrow.max_increment = 0.001;
  narrow.force_hard = 300;
  narrow.timeout = 100;  // not compared
  EXPECT_EQ(ErrorOf(narrow, bench), "");
}

TEST(LimitsCheck, MillimetresTypedIntoMetresAreAUnitSlip) {
  SafetyLimits runner;
  runner.stroke_min = -150;
  runner.stroke_max = 150;
  const std::string msg = ErrorOf(runner, SafetyLimits{});
  EXPECT_NE(msg.find("substructures.r1.safety.stroke_min = -150 m"), std::string::npos) << msg;
  EXPECT_NE(msg.find("0.15 m"), std::string::npos) << msg;
  EXPECT_NE(msg.find("about 1000 times"), std::string::npos) << msg;
}

TEST(LimitsCheck, EachLimitIsCompared) {
  for (int which = 0; which < 4; ++which) {
    SafetyLimits runner;
    if (which == 0) runner.stroke_min = -0.2;
    if (which == 1) runner.stroke_max = 0.2;
    if (which == 2) runner.max_increment = 0.01;
    if (which == 3) runner.force_hard = 2e4;
    const char* names[] = {"stroke_min", "stroke_max", "max_increment", "force_hard"};
    const std::string msg = ErrorOf(runner, SafetyLimits{});
    EXPECT_NE(msg.find(std::string("safety.") + names[which]), std::string::npos) << msg;
    EXPECT_EQ(msg.find("about 1000"), std::string::npos) << msg;  // no unit-slip hint at 1.3x
  }
}

}  // namespace
}  // namespace hybridtest::transfer
