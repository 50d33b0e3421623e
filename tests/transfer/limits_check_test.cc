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

TEST(LimitsCheck, KilonewtonsTypedIntoNewtonsAreAUnitSlipToo) {
  // The other direction: far inside the bench's by a factor of 1000.
  SafetyLimits bench;
  bench.force_soft = 250;
  bench.force_hard = 300;
  SafetyLimits runner = bench;
  runner.force_soft = 0.25;
  runner.force_hard = 0.3;
  const std::string msg = ErrorOf(runner, bench);
  EXPECT_NE(msg.find("substructures.r1.safety.force_hard = 0.3 N is about 1/1000"),
            std::string::npos) << msg;
  EXPECT_NE(msg.find("300 N"), std::string::npos) << msg;
  // A specimen limit 1/10 or 1/100 of the bench's is ordinary, and so is 1/10^4.
  for (double f : {30.0, 3.0, 0.03}) {
    runner.force_hard = f;
    EXPECT_EQ(ErrorOf(runner, bench), "") << f;
  }
  runner = bench;
  runner.stroke_max = bench.stroke_max / 1000;
  EXPECT_NE(ErrorOf(runner, bench).find("stroke_max"), std::string::npos);
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
