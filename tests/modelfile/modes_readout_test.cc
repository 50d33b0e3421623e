// How `hybridtest modes` reads its modes (issue 50): an operating point that is not an
// equilibrium is warned about with its residual; unstable modes are marked; modes are named by
// their dominant coordinates and by the model file's `modes:` labels (the Whipple bicycle's
// weave, capsize and castering, against Table 2 of Meijaard et al. 2007 in
// bicycle_modes_test.cc); shapes are normalised on the coordinates a reader looks at.
#include <fmt/format.h>
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <complex>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>

#include "support/run_command.h"
#include "support/temp_dir.h"

namespace hybridtest {
namespace {

using ::testing::HasSubstr;

const std::string kSource = HYBRIDTEST_SOURCE_DIR;
const std::string kBicycle = kSource + "/examples/models/whipple_bicycle.yaml";

nlohmann::json ModesJson(const std::string& args) {
  const auto [status, out] =
      testing::RunCommand(fmt::format("{} modes {} --json", HYBRIDTEST_BINARY, args), 120, false);
  EXPECT_EQ(status, 0) << out;
  return nlohmann::json::parse(out);
}

// The first mode labelled `label` (its eigenvalue and flags), or null.
nlohmann::json Labelled(const nlohmann::json& j, const std::string& label) {
  for (const auto& m : j["modes"]) {
    if (m["label"] == label) return m;
  }
  return nullptr;
}

TEST(ModesReadout, ACrankSliderTurningIsWarnedAboutWithItsResidual) {
  const std::string model = kSource + "/examples/models/slider_crank.yaml";
  const auto [status, out] = testing::RunCommand(
      fmt::format("{} modes {} --at u=3,0,0", HYBRIDTEST_BINARY, model), 60, false);
  ASSERT_EQ(status, 0) << out;
  EXPECT_THAT(out, HasSubstr("warning: not an equilibrium: max |u̇| = "));
  EXPECT_THAT(out, HasSubstr("--steady"));
  const nlohmann::json j = ModesJson(model + " --at u=3,0,0");
  EXPECT_FALSE(j["equilibrium"].get<bool>());
  EXPECT_GT(j["residual"].get<double>(), 1e-3);
}

TEST(ModesReadout, TheUprightBicycleIsAnEquilibrium) {
  const auto [status, out] = testing::RunCommand(
      fmt::format("{} modes {} --set v=5", HYBRIDTEST_BINARY, kBicycle), 120, false);
  ASSERT_EQ(status, 0) << out;
  EXPECT_THAT(out, ::testing::Not(HasSubstr("not an equilibrium")));
}

TEST(ModesReadout, AtThreeMetresPerSecondTheWeaveIsUnstableAndNamed) {
  const nlohmann::json j = ModesJson(kBicycle + " --set v=3");
  EXPECT_TRUE(j["equilibrium"].get<bool>());
  const nlohmann::json weave = Labelled(j, "weave");
  ASSERT_FALSE(weave.is_null()) << j["modes"].dump();
  EXPECT_NEAR(weave["real"].get<double>(), 1.70675605663975, 1e-8);  // Table 2, v = 3
  EXPECT_TRUE(weave["unstable"].get<bool>());
  const nlohmann::json capsize = Labelled(j, "capsize");
  ASSERT_FALSE(capsize.is_null()) << j["modes"].dump();
  EXPECT_NEAR(capsize["real"].get<double>(), -2.63366137253667, 1e-8);
  EXPECT_FALSE(capsize["unstable"].get<bool>());
  const nlohmann::json castering = Labelled(j, "castering");
  ASSERT_FALSE(castering.is_null()) << j["modes"].dump();
  EXPECT_NEAR(castering["real"].get<double>(), -10.35101467245920, 1e-8);
  const auto [status, out] = testing::RunCommand(
      fmt::format("{} modes {} --set v=3", HYBRIDTEST_BINARY, kBicycle), 120, false);
  ASSERT_EQ(status, 0) << out;
  EXPECT_THAT(out, HasSubstr("UNSTABLE"));
  EXPECT_THAT(out, HasSubstr("weave ("));
  EXPECT_THAT(out, HasSubstr("capsize (q4"));  // lean first
  EXPECT_THAT(out, HasSubstr("unstable mode(s)"));
}

TEST(ModesReadout, AtFiveMetresPerSecondWeaveAndCapsizeAreStableAndTheCapsizeReadsAsLean) {
  const nlohmann::json j = ModesJson(kBicycle + " --set v=5");
  const nlohmann::json weave = Labelled(j, "weave");
  const nlohmann::json capsize = Labelled(j, "capsize");
  ASSERT_FALSE(weave.is_null()) << j["modes"].dump();
  ASSERT_FALSE(capsize.is_null()) << j["modes"].dump();
  EXPECT_NEAR(weave["real"].get<double>(), -0.77534188219585, 1e-8);
  EXPECT_NEAR(capsize["real"].get<double>(), -0.32286642900409, 1e-8);
  EXPECT_FALSE(weave["unstable"].get<bool>());
  EXPECT_FALSE(capsize["unstable"].get<bool>());
  for (const auto& m : j["modes"]) EXPECT_FALSE(m["unstable"].get<bool>()) << m.dump();
  // The capsize's shape is normalised on lean (q4 = 1), not on the rear contact's drift.
  const auto& states = j["states"];
  const auto q4 = std::find(states.begin(), states.end(), "q4") - states.begin();
  EXPECT_NEAR(capsize["shape_real"][static_cast<std::size_t>(q4)].get<double>(), 1.0, 1e-12);
  EXPECT_EQ(capsize["dominant"][0], "q4");
}

TEST(ModesReadout, ModeLabelsAreCheckedWhereTheyAreWritten) {
  const std::filesystem::path dir = std::filesystem::temp_directory_path() / "modes_readout_test";
  std::filesystem::create_directories(dir);
  const std::string good = kSource + "/examples/models/slider_crank.yaml";
  const std::string text = test_support::ReadText(good);
  const auto run = [&](const std::string& extra) {
    const std::string path = (dir / "m.yaml").string();
    std::ofstream(path) << text << extra;
    return testing::RunCommand(fmt::format("{} modes {}", HYBRIDTEST_BINARY, path), 60, true);
  };
  auto [status, out] = run("modes:\n  labels:\n    - {name: a, dominat: q1}\n");
  EXPECT_EQ(status, 2) << out;
  EXPECT_THAT(out, HasSubstr("modes.labels[0]"));
  EXPECT_THAT(out, HasSubstr("unknown key 'dominat'"));
  std::tie(status, out) = run("modes:\n  labels:\n    - {name: a, dominant: q3}\n");
  EXPECT_EQ(status, 2) << out;
  EXPECT_THAT(out, HasSubstr("'q3' is not an independent coordinate"));
  EXPECT_THAT(out, HasSubstr("q1"));
  std::tie(status, out) = run("modes:\n  labels:\n    - {name: a, oscillatory: maybe}\n");
  EXPECT_EQ(status, 2) << out;
  EXPECT_THAT(out, HasSubstr("modes.labels[0].oscillatory"));
  std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace hybridtest
