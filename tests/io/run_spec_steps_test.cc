// SchemeSpec::steps of a RunSpec filled in code: a fixed-step run takes exactly `steps` steps,
// so a count that does not span the duration is refused instead of ending the run early.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "hybridtest/common/error.h"
#include "hybridtest/io/run_spec.h"
#include "hybridtest/io/run_spec_yaml.h"

namespace hybridtest::io {
namespace {

using ::testing::AllOf;
using ::testing::HasSubstr;

RunSpec Rotor() {
  return CompileRunSpec(ParseSimulationConfig(YamlInput::FromText(
      "model: {name: rotor, blades: 3}\nintegrator: {tableau: heun, dt: 0.001}\nduration: 0.1\n",
      "steps.yaml")));
}

std::string ErrorOf(const RunSpec& spec) {
  try {
    ValidateRunSpec(spec);
  } catch (const ConfigError& e) {
    return e.what();
  }
  return "(no error)";
}

TEST(RunSpecSteps, ACountThatDoesNotSpanTheDurationIsRefused) {
  RunSpec spec = Rotor();
  EXPECT_EQ(spec.scheme.steps, 100);
  EXPECT_EQ(ErrorOf(spec), "(no error)");
  spec.scheme.duration = 0.2;  // steps left at 100: the run would end at 0.1 s
  EXPECT_THAT(ErrorOf(spec), AllOf(HasSubstr("scheme.steps = 100"), HasSubstr("200 steps"),
                                   HasSubstr("end at t = 0.1 s")));
  spec.scheme.steps = StepCount(spec.scheme.duration, spec.scheme.dt);
  EXPECT_EQ(spec.scheme.steps, 200);
  EXPECT_EQ(ErrorOf(spec), "(no error)");
  spec.scheme.steps = 201;  // late, too
  EXPECT_THAT(ErrorOf(spec), HasSubstr("scheme.steps = 201"));
}

TEST(RunSpecSteps, StepCountWantsAWholeNumberOfFixedSteps) {
  EXPECT_EQ(StepCount(10.0, 0.002), 5000);
  EXPECT_EQ(StepCount(0.3, 0.1), 3);  // 0.3 / 0.1 is 2.9999999999999996 in doubles
  EXPECT_THROW(StepCount(0.1005, 0.001), ConfigError);
  EXPECT_EQ(StepCount(0.10049, 0.001, /*whole=*/false), 100);  // an adaptive scheme's estimate
  EXPECT_THROW(StepCount(0.0005, 0.001), ConfigError);
  EXPECT_THROW(StepCount(-1.0, 0.001), ConfigError);
  EXPECT_THROW(StepCount(1e12, 1e-3), ConfigError);
}

}  // namespace
}  // namespace hybridtest::io
