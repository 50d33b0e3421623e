// `hybridtest plan` on setups other than the paper's, with real processes:
//   - a lever (setup scale 0.5): the recommended config, pasted as printed, runs, and its run
//     is within the tolerance of plan's own reference (the emulated specimen seen through the
//     lever), so plan judged the candidates against the right thing;
//   - limits that the reference itself passes: plan warns before the candidates, naming the
//     slot, the limit and the time, and its closing advice is about that limit, not steps;
//   - the paper's scheme is shown as a baseline row, and noisy benches are judged over seeds;
//   - two actuators on a yielding specimen are judged against the specimen law through the setup.
#include <fmt/format.h>
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <regex>
#include <sstream>
#include <string>

#include "hybridtest/io/run_reader.h"
#include "hybridtest/io/run_spec_yaml.h"
#include "hybridtest/runner/plan.h"
#include "integration/bench_process.h"
#include "support/temp_dir.h"

namespace hybridtest {
namespace {

namespace fs = std::filesystem;
using testing::RunCommand;
using ::testing::HasSubstr;
using ::testing::Not;

const std::string kSource = HYBRIDTEST_SOURCE_DIR;
const std::string kBinary = HYBRIDTEST_BINARY;

fs::path OutDir() {
  static const fs::path dir = test_support::FreshTempDir("plan_setups");
  return dir;
}

std::string ReadText(const fs::path& path) {
  std::ifstream in(path);
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

// examples/rotor/emulated-fast.yaml in `dir`, beside a copy of its bench, with `edit` applied
// to its text (a regex replacement).
fs::path FastConfig(const fs::path& dir, const std::string& pattern, const std::string& with) {
  fs::create_directories(dir);
  fs::copy_file(kSource + "/examples/rotor/bench-cantilever.yaml", dir / "bench-cantilever.yaml",
                fs::copy_options::overwrite_existing);
  std::string text = ReadText(kSource + "/examples/rotor/emulated-fast.yaml");
  const std::string edited = std::regex_replace(text, std::regex(pattern), with);
  EXPECT_NE(edited, text) << "the example no longer has " << pattern;
  const fs::path config = dir / "config.yaml";
  std::ofstream(config) << edited;
  return config;
}

TEST(PlanSetups, OnALeverTheRecommendationRunsAsPastedAndMeetsTheTolerance) {
  const fs::path dir = OutDir() / "lever";
  const fs::path config = FastConfig(dir, R"(scale: 1\b)", "scale: 0.5");
  const fs::path keep = dir / "plan";
  const auto [status, output] = RunCommand(
      fmt::format("{} plan {} --seeds 2 --keep {}", kBinary, config.string(), keep.string()), 900);
  ASSERT_EQ(status, 0) << output;
  EXPECT_THAT(output, HasSubstr("baseline: the paper's scheme (heun, dt 0.001 s)"));
  EXPECT_THAT(output, HasSubstr("worst of 2 noise seeds"));
  // Two seeds of each candidate were run and kept.
  EXPECT_TRUE(fs::exists(keep / "candidate-0-seed2.csv"));
  const auto start = output.find("\n---\n");
  ASSERT_NE(start, std::string::npos) << output;
  const fs::path recommended = dir / "recommended.yaml";
  std::ofstream(recommended) << output.substr(start + 5);
  const fs::path csv = dir / "recommended.csv";
  const auto [run_status, run_output] = RunCommand(
      fmt::format("{} run {} --out {} --quiet", kBinary, recommended.string(), csv.string()), 600);
  ASSERT_EQ(run_status, 0) << run_output;
  // The actual run against plan's reference: the emulated cantilever through the lever.
  const io::RunSpec spec = io::LoadRunSpec(recommended.string());
  const double error = runner::RelativeError(spec.model.model, io::LoadRun(csv.string()),
                                             io::LoadRun((keep / "reference.csv").string()), 0);
  EXPECT_LE(error, 0.01);
  // A lever halves the actuator's motion: the reference's blade tip is not the identity
  // setup's (the wrong reference would be the configured K0 as a spring at the slot).
  EXPECT_GT(error, 0.0);
}

// The yielding example: plan's recommendation, pasted and run, reaches 1 % against
// `simulate` with the same Bouc–Wen law as a numerical substructure (RK4 at 0.1 ms).
TEST(PlanSetups, OnTheYieldingExampleTheRecommendationMeetsTheNumericalReference) {
  const fs::path dir = OutDir() / "yielding";
  fs::create_directories(dir);
  const auto [status, output] = RunCommand(
      fmt::format("{} plan {}/examples/rotor/yielding.yaml --seeds 2", kBinary, kSource), 900);
  ASSERT_EQ(status, 0) << output;
  const auto start = output.find("\n---\n");
  ASSERT_NE(start, std::string::npos) << output;
  fs::copy_file(kSource + "/examples/rotor/bench-bouc-wen.yaml", dir / "bench-bouc-wen.yaml",
                fs::copy_options::overwrite_existing);
  const fs::path recommended = dir / "recommended.yaml";
  std::ofstream(recommended) << output.substr(start + 5);
  const fs::path csv = dir / "recommended.csv", ref = dir / "reference.csv";
  const auto [run_status, run_output] = RunCommand(
      fmt::format("{} run {} --out {} --quiet", kBinary, recommended.string(), csv.string()), 600);
  ASSERT_EQ(run_status, 0) << run_output;
  const auto [ref_status, ref_output] = RunCommand(
      fmt::format("{} simulate {}/examples/rotor/yielding-reference.yaml --out {} --quiet",
                  kBinary, kSource, ref.string()), 600);
  ASSERT_EQ(ref_status, 0) << ref_output;
  const io::RunSpec spec = io::LoadRunSpec(recommended.string());
  const double error = runner::RelativeError(spec.model.model, io::LoadRun(csv.string()),
                                             io::LoadRun(ref.string()), 0);
  EXPECT_LE(error, 0.01) << output;
  // The monotone approach of this bench: no force reversal within any move.
  EXPECT_THAT(output, Not(HasSubstr("the specimen force reversed")));
}

TEST(PlanSetups, AReferenceBeyondTheForceLimitIsNamedBeforeTheCandidates) {
  const fs::path dir = OutDir() / "limit";
  // The blade tip carries ~120 N in this test: a 100 N hard limit stops every scheme.
  fs::path config = FastConfig(dir, R"(force_soft: 250)", "force_soft: 90");
  {
    std::string text = ReadText(config);
    text = std::regex_replace(text, std::regex(R"(force_hard: 300)"), "force_hard: 100");
    std::ofstream(config) << text;
  }
  const auto [status, output] =
      RunCommand(fmt::format("{} plan {} --seeds 1", kBinary, config.string()), 900);
  ASSERT_EQ(status, 0) << output;
  const auto warning = output.find("warning: the reference itself reaches the specimen force");
  ASSERT_NE(warning, std::string::npos) << output;
  EXPECT_LT(warning, output.find("evaluations")) << "the warning must come before the table";
  EXPECT_THAT(output, HasSubstr("substructures.r1.safety.force_hard = 100 N"));
  EXPECT_THAT(output, HasSubstr("every candidate will stop there"));
  EXPECT_THAT(output, HasSubstr("no scheme can run this test as configured"));
  EXPECT_THAT(output, Not(HasSubstr("Tighten the steps")));
}

TEST(PlanSetups, WithinTheLimitsThereIsNoWarning) {
  const fs::path dir = OutDir() / "no_limit";
  const fs::path config = FastConfig(dir, R"(force_soft: 250)", "force_soft: 260");
  const io::RunSpec spec = io::LoadRunSpec(config.string());
  io::RunData reference;
  reference.channels = {{"t", "s", ""}};
  // A reference at rest: nothing reaches a limit.
  for (const auto& q : spec.model.model.coordinates()) reference.channels.push_back({q.name, "m", ""});
  for (const auto& s : spec.model.model.slots()) reference.channels.push_back({s.info.name, "N", ""});
  reference.values = Eigen::MatrixXd::Zero(3, static_cast<Eigen::Index>(reference.channels.size()));
  reference.values(1, 0) = 1.0;
  reference.values(2, 0) = 2.0;
  EXPECT_TRUE(runner::ReferenceLimitWarnings(spec, reference).empty());
  // The same rows with the slot force at 400 N pass force_hard (300 N) at t = 1 s.
  const int r1 = reference.Column("r1");
  reference.values(1, r1) = -400.0;
  reference.values(2, r1) = 500.0;
  const auto warnings = runner::ReferenceLimitWarnings(spec, reference);
  ASSERT_EQ(warnings.size(), 1u);
  EXPECT_EQ(warnings[0].limit, "force_hard");
  EXPECT_EQ(warnings[0].slot, "r1");
  EXPECT_DOUBLE_EQ(warnings[0].t, 1.0);
  EXPECT_DOUBLE_EQ(warnings[0].value, -400.0);
}

// Two actuators on a yielding specimen (a biaxial Bouc–Wen law in actuator coordinates): plan's
// reference is the specimen law seen through the setup, r = Tᵀ F(T d), so a scheme that
// follows the specimen is judged close (a reference with the initial stiffness alone would put
// every candidate about 100 % off).
TEST(PlanSetups, TwoActuatorsOnAYieldingSpecimenAreJudgedAgainstTheirOwnLaw) {
  const auto [status, output] = RunCommand(
      fmt::format("{} plan {}/examples/06_blade_two_actuators/bouc-wen.yaml", kBinary, kSource),
      900);
  ASSERT_EQ(status, 0) << output;
  std::smatch m;
  ASSERT_TRUE(std::regex_search(output, m,
                                std::regex(R"(mr-os, dt 0\.02 s\s+(\d+)\s+\S+\s+([0-9.]+) %)")))
      << output;
  EXPECT_LT(std::stod(m[2].str()), 1.0) << output;
  EXPECT_THAT(output, HasSubstr("recommended (fewest specimen evaluations"));
}

}  // namespace
}  // namespace hybridtest
