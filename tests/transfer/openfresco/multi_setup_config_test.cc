// The `openfresco:` section of a bench file with `actuators:` (setup_config.h): T of one row per
// actuator, p0 per actuator, K_a from `initial_stiffness` or the specimen; errors name the key.
#include <gtest/gtest.h>

#include <string>

#include "hybridtest/common/error.h"
#include "hybridtest/common/yaml_input.h"
#include "hybridtest/transfer/emulated_bench.h"
#include "hybridtest/transfer/openfresco/setup_config.h"

namespace hybridtest::transfer::openfresco {
namespace {

const std::string kExample = HYBRIDTEST_SOURCE_DIR "/examples/06_blade_two_actuators/";

ExpSetup Parse(const std::string& section) {
  const EmulatedBenchSpec bench = LoadEmulatedBenchSpec(kExample + "bench-2act.yaml");
  const YamlInput in = YamlInput::FromText("openfresco: " + section, "b.yaml");
  return ParseSetup(in.root()["openfresco"], "b.yaml: openfresco", bench);
}

std::string ErrorOf(const std::string& section) {
  try {
    Parse(section);
  } catch (const ConfigError& e) {
    return e.what();
  }
  return "accepted";
}

TEST(OpenFrescoMultiSetupConfig, TheExampleFileGivesTheSetup) {
  const EmulatedBenchSpec bench = LoadEmulatedBenchSpec(kExample + "bench-2act-openfresco.yaml");
  const ExpSetup s = LoadSetup(kExample + "bench-2act-openfresco.yaml", bench);
  EXPECT_EQ(s.actuators, 2);
  EXPECT_EQ(s.dofs(), 2);
  EXPECT_EQ(s.transform, (std::vector<double>{1.0, 0.0, 0.6, 0.8}));
  EXPECT_EQ(s.p0s, (std::vector<double>{0.020, 0.030}));
  EXPECT_EQ(s.stiffness_matrix, (std::vector<double>{5000, 1200, 1200, 3000}));  // the specimen's
  EXPECT_EQ(s.wire_units.length_name, "mm");
}

TEST(OpenFrescoMultiSetupConfig, InitialStiffnessMatrixAndWideTransform) {
  const ExpSetup s = Parse("{transform: [[0.6, -0.8, -0.6, 0.8], [0, 1, 0, -1]], "
                           "initial_stiffness: [[5000, 1200], [800, 3000]]}");
  EXPECT_EQ(s.dofs(), 4);
  EXPECT_EQ(s.stiffness_matrix, (std::vector<double>{5000, 1200, 800, 3000}));
}

TEST(OpenFrescoMultiSetupConfig, ErrorsNameTheKey) {
  std::string what = ErrorOf("{transform: [[1, 0]]}");
  EXPECT_NE(what.find("openfresco.transform"), std::string::npos) << what;
  EXPECT_NE(what.find("2 rows (one per actuator"), std::string::npos) << what;
  what = ErrorOf("{transform: [[1, 0], [0, 1, 0]]}");
  EXPECT_NE(what.find("openfresco.transform[1]"), std::string::npos) << what;
  what = ErrorOf("{transform: [[1, 2], [2, 4]]}");
  EXPECT_NE(what.find("linearly independent"), std::string::npos) << what;
  what = ErrorOf("{transform: [[1, 0], [0, 1]], initial_stiffness: [[1, 2, 3], [4, 5, 6]]}");
  EXPECT_NE(what.find("openfresco.initial_stiffness[0]"), std::string::npos) << what;
  EXPECT_NE(what.find("2 × 2 in N/m"), std::string::npos) << what;
  what = ErrorOf("{transform: [[1, 0], [0, 1]], stiffness: 3}");
  EXPECT_NE(what.find("stiffness"), std::string::npos) << what;
}

}  // namespace
}  // namespace hybridtest::transfer::openfresco
