// plan for a real-time run (runner/plan_real_time.h): the storey on the servo-hydraulic plant
// for 2 s. Uncompensated it is predicted unstable (and does not track), both compensators are
// stable, ATS tracks best and is recommended; the recommendation's YAML selects it.
#include "hybridtest/runner/plan_real_time.h"

#include <gtest/gtest.h>

#include <fstream>
#include <string>

#include "hybridtest/common/error.h"
#include "support/temp_dir.h"

namespace hybridtest::runner {
namespace {

namespace fs = std::filesystem;
const std::string kDir = std::string(HYBRIDTEST_SOURCE_DIR) + "/examples/real-time/";

// storey.yaml (uncompensated) for 2 s, written where its model file is found.
std::string StoreyConfig(const fs::path& dir, bool real_time = true) {
  std::string text = test_support::ReadText(kDir + "storey.yaml");
  auto replace = [&](const std::string& from, const std::string& to) {
    text.replace(text.find(from), from.size(), to);
  };
  replace("duration: 10.0", "duration: 2.0");
  replace("file: storey.model.yaml", "file: " + kDir + "storey.model.yaml");
  if (!real_time) {  // the block, through its last key
    const auto from = text.find("real_time:");
    const auto to = text.find("force: true\n", from) + 12;
    text.erase(from, to - from);
  }
  const fs::path path = dir / "storey.yaml";
  std::ofstream(path) << text;
  return path.string();
}

TEST(PlanRealTime, CompensatorsAndStepsOfTheStorey) {
  const fs::path dir = test_support::FreshTempDir("plan_real_time");
  long calls = 0;
  RealTimePlanOptions options;
  options.on_result = [&](std::size_t i, std::size_t n, const RealTimePlanResult&) {
    EXPECT_EQ(static_cast<long>(i), calls++);
    EXPECT_EQ(n, 6u);
  };
  const auto results = PlanRealTime(StoreyConfig(dir), options);
  ASSERT_EQ(results.size(), 6u);
  EXPECT_EQ(calls, 6);
  for (std::size_t k = 0; k < 6; k += 3) {
    const RealTimePlanResult& none = results[k];
    const RealTimePlanResult& poly = results[k + 1];
    const RealTimePlanResult& ats = results[k + 2];
    EXPECT_EQ(none.compensator, "none");
    EXPECT_EQ(poly.compensator, "polynomial");
    EXPECT_EQ(ats.compensator, "ats");
    EXPECT_EQ(none.dt, ats.dt);
    // The vRTHS plant's ~22 ms against a critical delay of ~6 ms.
    EXPECT_TRUE(none.unstable);
    EXPECT_GT(none.remaining_delay, 0.015);
    EXPECT_NEAR(none.critical_delay, 0.006, 0.001);
    EXPECT_GT(none.J1_ms, 15.0);
    EXPECT_FALSE(poly.unstable);
    EXPECT_FALSE(ats.unstable);
    EXPECT_TRUE(poly.ok) << poly.failure;
    EXPECT_TRUE(ats.ok) << ats.failure;
    EXPECT_NEAR(ats.compensation, none.remaining_delay, 1e-3);  // started from the plant's
    EXPECT_LT(ats.J2, poly.J2);
    EXPECT_LT(poly.J2, none.J2 / 5.0);
  }
  EXPECT_NEAR(results[3].dt, results[0].dt / 2, 1e-15);
  const auto best = RecommendRealTime(results);
  ASSERT_TRUE(best.has_value());
  EXPECT_EQ(best->compensator, "ats");
  const std::string yaml = RealTimeCandidateYaml(StoreyConfig(dir), *best);
  EXPECT_NE(yaml.find("method: ats"), std::string::npos) << yaml;
  EXPECT_NE(yaml.find("servo_hydraulic"), std::string::npos) << yaml;
}

TEST(PlanRealTime, AConfigWithoutRealTimeIsRefused) {
  const fs::path dir = test_support::FreshTempDir("plan_real_time_no");
  try {
    PlanRealTime(StoreyConfig(dir, false));
    FAIL() << "expected a ConfigError";
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("no `real_time:` block"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace hybridtest::runner
