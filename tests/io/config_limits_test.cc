// Range checks of every count derived from user numbers (issue 10): steps, blades, list sizes;
// non-UTF-8 input; and the dry-run output estimate against the free disk space.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>

#include "hybridtest/common/error.h"
#include "hybridtest/io/config.h"
#include "hybridtest/io/output_budget.h"
#include "hybridtest/io/substructure_config.h"

namespace hybridtest::io {
namespace {

using ::testing::AllOf;
using ::testing::HasSubstr;

std::string ErrorOf(const std::string& text) {
  try {
    const SimulationConfig cfg = ParseSimulationConfig(YamlInput::FromText(text, "cfg.yaml"));
    MakeSubstructures(cfg, {});
  } catch (const ConfigError& e) {
    return e.what();
  }
  return "(no error)";
}

const std::string kRotor = "model: {name: rotor, blades: 3}\n";
const std::string kHeun = "integrator: {tableau: heun, dt: 1}\n";

TEST(ConfigLimits, StepCountIsRangeCheckedBeforeConversion) {
  EXPECT_THAT(ErrorOf(kRotor + kHeun + "duration: 1e19\n"),
              AllOf(HasSubstr("cfg.yaml:3: duration"), HasSubstr("at most 1000000000")));
  EXPECT_THAT(ErrorOf(kRotor + kHeun + "duration: 1e12\n"), HasSubstr("at most"));
  EXPECT_THAT(ErrorOf(kRotor + "integrator: {tableau: heun, dt: 1e-300}\nduration: 1e300\n"),
              HasSubstr("steps"));
  EXPECT_EQ(ErrorOf(kRotor + kHeun + "duration: 1e9\n"), "(no error)");
}

TEST(ConfigLimits, BladesAreBoundedBeforeAnythingIsAllocated) {
  const std::string rest = "integrator: {tableau: heun, dt: 0.001}\nduration: 1\n";
  EXPECT_THAT(ErrorOf("model: {name: rotor, blades: 1e9}\n" + rest),
              AllOf(HasSubstr("model.blades"), HasSubstr("from 1 to 31")));
  EXPECT_THAT(ErrorOf("model: {name: rotor, blades: 2.5}\n" + rest), HasSubstr("model.blades"));
  EXPECT_EQ(ErrorOf("model: {name: rotor, blades: 31}\n" + rest), "(no error)");
}

TEST(ConfigLimits, ScalarWhereAMappingBelongsNamesTheKey) {
  const std::string head = kRotor + "integrator: {tableau: heun, dt: 0.001}\nduration: 0.01\n" +
                           "substructures:\n  r1:\n    type: physical\n"
                           "    transfer: {type: loopback, law: {type: linear, stiffness: 1}}\n";
  EXPECT_THAT(ErrorOf(head + "    safety: 5\n"),
              AllOf(HasSubstr("substructures.r1.safety"), HasSubstr("a mapping")));
  EXPECT_THAT(ErrorOf(head + "    safety: [1, 2]\n"), HasSubstr("substructures.r1.safety"));
  EXPECT_THAT(ErrorOf(head + "    safety: defaults\n    setup: 5\n"),
              HasSubstr("substructures.r1.setup"));
}

TEST(ConfigLimits, APhysicalSlotStatesItsLimitsOrAcknowledgesTheDefaults) {
  const std::string head = kRotor + "integrator: {tableau: heun, dt: 0.001}\nduration: 0.01\n" +
                           "substructures:\n  r1:\n    type: physical\n"
                           "    transfer: {type: loopback, law: {type: linear, stiffness: 1}}\n";
  EXPECT_THAT(ErrorOf(head), AllOf(HasSubstr("substructures.r1.safety: missing"),
                                   HasSubstr("safety: defaults"), HasSubstr("10000 N")));
  EXPECT_EQ(ErrorOf(head + "    safety: defaults\n"), "(no error)");
  EXPECT_THAT(ErrorOf(head + "    safety: default\n"),
              AllOf(HasSubstr("substructures.r1.safety"), HasSubstr("`defaults`")));
}

TEST(ConfigLimits, NonScalarKeysAreConfigErrorsNamingTheSection) {
  const std::string rest = "integrator: {tableau: heun, dt: 0.001}\nduration: 1\n";
  EXPECT_THAT(ErrorOf("model: {name: rotor, parameters: {[1]: 2}}\n" + rest),
              HasSubstr("model.parameters"));
  EXPECT_THAT(ErrorOf("model: {name: rotor}\n" + rest + "substructures: {[r1]: {}}\n"),
              HasSubstr("substructures"));
}

TEST(ConfigLimits, ATokenInTheRunConfigIsRefused) {
  const std::string text = kRotor + "integrator: {tableau: heun, dt: 0.001}\nduration: 0.01\n" +
                           "substructures:\n  r1:\n    type: physical\n"
                           "    transfer: {type: remote, address: 127.0.0.1:1, token: s3cret}\n"
                           "    safety: defaults\n";
  EXPECT_THAT(ErrorOf(text), AllOf(HasSubstr("substructures.r1.transfer.token"),
                                   HasSubstr("token_file"), HasSubstr(".meta.json")));
}

TEST(ConfigLimits, HugeListsAndNonUtf8AreConfigErrors) {
  std::string list = "initial_state: {q: [";
  for (std::size_t i = 0; i <= kMaxListLength; ++i) list += "0,";
  list += "0]}\n";
  EXPECT_THAT(ErrorOf(kRotor + kHeun + "duration: 1\n" + list),
              AllOf(HasSubstr("initial_state.q"), HasSubstr("at most 100000")));
  EXPECT_THAT(ErrorOf(kRotor + kHeun + "duration: 1\n# caf\xE9\n"),
              AllOf(HasSubstr("not valid UTF-8"), HasSubstr("line 4")));
}

TEST(ConfigLimits, FileTooLargeOrWithANonUtf8PathIsAConfigError) {
  const auto dir = std::filesystem::temp_directory_path() / "hybridtest_config_limits";
  std::filesystem::create_directories(dir);
  const auto big = (dir / "big.yaml").string();
  {
    std::ofstream out(big);
    out << kRotor << std::string(kMaxConfigBytes, '#') << "\n";
  }
  EXPECT_THROW(LoadSimulationConfig(big), ConfigError);
  EXPECT_THROW(LoadSimulationConfig((dir / "caf\xE9.yaml").string()), ConfigError);
  std::filesystem::remove_all(dir);
}

TEST(OutputBudget, EstimateScalesWithStepsAndChannels) {
  EXPECT_EQ(EstimateOutputBytes(9, 10, 2, 0), 10u * 10u * kBytesPerValue);
  EXPECT_EQ(EstimateOutputBytes(9, 10, 2, 7), (100u + 9u * 2u * 7u) * kBytesPerValue);
  EXPECT_GT(EstimateOutputBytes(1'000'000'000L, 12, 4, 12), 1e12);
}

TEST(OutputBudget, ARunThatDoesNotFitIsRefusedWithTheNumbers) {
  const std::string path =
      (std::filesystem::temp_directory_path() / "no" / "such" / "dir" / "run.csv").string();
  EXPECT_NO_THROW(CheckOutputFits(path, 1000));
  try {
    CheckOutputFits(path, EstimateOutputBytes(1'000'000'000L, 100, 4, 100) * 1000);
    FAIL() << "expected ConfigError";
  } catch (const ConfigError& e) {
    EXPECT_THAT(std::string(e.what()), AllOf(HasSubstr("would write about"), HasSubstr("free")));
  }
}

}  // namespace
}  // namespace hybridtest::io
