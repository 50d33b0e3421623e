// FMU substructures in whole runs: the rotor with blade 1 served by an FMU equals the same run
// with the built-in linear law (the paper's dummy test), with the stateless spring FMU and
// with the stateful Maxwell FMU whose dashpot is rigid (rolled back at every trial); an FMU
// error stops `hybridtest run` with the committed rows on disk; refusals exit 2.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <string>
#include <vector>

#include "fmi/fmi_test_support.h"
#include "hybridtest/io/run_spec_yaml.h"
#include "hybridtest/runner/session.h"
#include "support/run_command.h"

namespace hybridtest::fmi {
namespace {

namespace fs = std::filesystem;
using test::TestFmu;

class Rows final : public runner::SessionObserver {
 public:
  void OnCommit(const runner::CommitEvent& e) override {
    if (e.kind == runner::RowKind::kCommitted) rows.emplace_back(e.x.begin(), e.x.end());
  }
  std::vector<std::vector<double>> rows;
};

// The rotor (3 blades, Table 1) for `duration` s under `integrator`, with `substructures`.
std::string Config(const std::string& integrator, const std::string& substructures,
                   double duration = 2.0) {
  return "model: {name: rotor, blades: 3}\nintegrator: " + integrator +
         "\nduration: " + std::to_string(duration) + "\n" + substructures;
}

std::vector<std::vector<double>> RunRotor(const std::string& yaml) {
  static const fs::path dir = test_support::FreshTempDir("fmi_runs");
  static int count = 0;
  const fs::path file = dir / ("run" + std::to_string(++count) + ".yaml");
  test_support::WriteText(file, yaml);
  io::RunSpec spec = io::LoadRunSpec(file.string());
  spec.output.files = false;
  spec.quiet = true;
  runner::Session session(std::move(spec));
  Rows rows;
  session.AddObserver(rows);
  const auto result = session.Run();
  EXPECT_EQ(result.status, runner::SessionStatus::kFinished) << result.reason;
  return rows.rows;
}

double WorstDifference(const std::vector<std::vector<double>>& a,
                       const std::vector<std::vector<double>>& b) {
  EXPECT_EQ(a.size(), b.size());
  double worst = 0.0;
  for (std::size_t i = 0; i < std::min(a.size(), b.size()); ++i) {
    for (std::size_t j = 0; j < a[i].size(); ++j) worst = std::max(worst, std::abs(a[i][j] - b[i][j]));
  }
  return worst;
}

double Peak(const std::vector<std::vector<double>>& a, std::size_t j) {
  double peak = 0.0;
  for (const auto& row : a) peak = std::max(peak, std::abs(row[j]));
  return peak;
}

const std::string kHeun = "{tableau: heun, dt: 0.001}";
const std::string kLinear =
    "substructures:\n  r1: {type: numerical, law: {type: linear, stiffness: 7200}}\n";

TEST(FmuRun, SpringFmuEqualsTheBuiltInLinearLaw) {
  const auto reference = RunRotor(Config(kHeun, kLinear));
  const auto fmu = RunRotor(Config(kHeun, "substructures:\n  r1: {type: fmu, fmu: " + TestFmu("spring") +
                                         ", displacement: x, force: F, parameters: {k: 7200}}\n"));
  ASSERT_EQ(reference.size(), 2001u);
  EXPECT_GT(Peak(reference, 1), 1e-3);  // blade 1 deflects: the comparison means something
  EXPECT_LE(WorstDifference(reference, fmu), 1e-12);
}

// The Maxwell FMU with a rigid dashpot (c = 1e300: e^{−k h/c} = 1) is a spring of k, but the
// importer treats it as stateful: every trial restores the committed FMU state.
TEST(FmuRun, StatefulFmuRolledBackAtEveryTrialEqualsTheLinearLaw) {
  const auto reference = RunRotor(Config(kHeun, kLinear));
  const auto fmu = RunRotor(Config(kHeun, "substructures:\n  r1: {type: fmu, fmu: " +
                                         TestFmu("maxwell") + ", displacement: x, force: F, "
                                         "parameters: {k: 7200, c: 1e300}}\n"));
  EXPECT_LE(WorstDifference(reference, fmu), 1e-9);
}

TEST(FmuRun, Fmi3FmuEqualsTheLinearLaw) {
  const auto reference = RunRotor(Config(kHeun, kLinear));
  const auto fmu = RunRotor(Config(kHeun, "substructures:\n  r1: {type: fmu, fmu: " +
                                              TestFmu("maxwell3") + ", displacement: x, force: "
                                              "F, parameters: {k: 7200, c: 1e300}}\n"));
  EXPECT_LE(WorstDifference(reference, fmu), 1e-9);
}

// One FMU serving two slots (`slots: [r1, r2]`): equals the built-in coupled linear block.
TEST(FmuRun, TwoSlotFmuEqualsTheLinearBlock) {
  const std::string k = "[[7200, 1500], [1500, 6000]]";
  const auto reference = RunRotor(Config(
      kHeun, "substructures:\n  blade: {type: numerical, slots: [r1, r2], law: {type: linear, "
             "stiffness: " + k + "}}\n"));
  const auto fmu = RunRotor(Config(
      kHeun, "substructures:\n  blade: {type: fmu, slots: [r1, r2], fmu: " +
                 TestFmu("coupled_spring") + ", displacement: [x1, x2], force: [F1, F2], "
                 "parameters: {k11: 7200, k12: 1500, k21: 1500, k22: 6000}, "
                 "initial_stiffness: " + k + "}\n"));
  EXPECT_GT(Peak(reference, 2), 1e-3);
  EXPECT_LE(WorstDifference(reference, fmu), 1e-12);
  // The slots in the other order swap the FMU's springs: a different run.
  const auto swapped = RunRotor(Config(
      kHeun, "substructures:\n  blade: {type: fmu, slots: [r1, r2], fmu: " +
                 TestFmu("coupled_spring") + ", displacement: [x2, x1], force: [F2, F1], "
                 "parameters: {k11: 7200, k12: 1500, k21: 1500, k22: 6000}}\n"));
  EXPECT_GT(WorstDifference(reference, swapped), 1e-4);
}

// A soft dashpot makes the blade visibly different: the comparison above can fail.
TEST(FmuRun, ASoftDashpotChangesTheRun) {
  const auto reference = RunRotor(Config(kHeun, kLinear));
  const auto fmu = RunRotor(Config(kHeun, "substructures:\n  r1: {type: fmu, fmu: " +
                                         TestFmu("maxwell") + ", displacement: x, force: F, "
                                         "parameters: {k: 7200, c: 20}}\n"));
  EXPECT_GT(WorstDifference(reference, fmu), 1e-2 * Peak(reference, 1));
}

// Operator splitting needs K0: given in the config.
TEST(FmuRun, MrOsWithTheFmuEqualsMrOsWithTheLaw) {
  const std::string mros = "{scheme: mr-os, dt: 0.01, substep: 0.001}";
  const auto reference = RunRotor(Config(mros, kLinear));
  const auto fmu = RunRotor(Config(mros, "substructures:\n  r1: {type: fmu, fmu: " +
                                        TestFmu("maxwell") + ", displacement: x, force: F, "
                                        "parameters: {k: 7200, c: 1e300}, initial_stiffness: "
                                        "7200}\n"));
  EXPECT_LE(WorstDifference(reference, fmu), 1e-9);
}

TEST(FmuRun, FmuErrorStopsTheRunWithTheCommittedRowsOnDisk) {
  const auto dir = test_support::FreshTempDir("fmi_error_run");
  test_support::WriteText(dir / "fail.yaml",
                          Config(kHeun, "substructures:\n  r1: {type: fmu, fmu: " +
                                            TestFmu("maxwell") + ", displacement: x, force: F, "
                                            "parameters: {k: 7200, c: 50, fail_at: 0.5}}\n"));
  const auto [status, out] = testing::RunCommand(std::string(HYBRIDTEST_BINARY) + " run " +
                                                 (dir / "fail.yaml").string() + " --out " +
                                                 (dir / "fail.csv").string());
  EXPECT_EQ(status, 4) << out;
  EXPECT_NE(out.find("fail_at reached"), std::string::npos) << out;
  EXPECT_NE(out.find("maxwell.fmu: fmi2DoStep"), std::string::npos) << out;
  // Rows up to t = 0.499 s were committed (the step to 0.5 s fails at its second stage... or
  // at 0.5 + h): the journal holds them.
  const std::string csv = test_support::ReadText(dir / "fail.csv");
  std::size_t lines = 0;
  for (char c : csv) lines += c == '\n';
  EXPECT_GE(lines, 500u) << csv.substr(0, 400);
}

// Every refusal of issues 35 and 45 through the binary: exit 2, naming the FMU file and the variable
// or capability (the messages themselves: fmu_refusal_test.cc).
TEST(FmuRun, RefusalsExitTwoNamingTheFmuAndTheVariableOrCapability) {
  const auto dir = test_support::FreshTempDir("fmi_refusal_run");
  struct Case {
    std::string fmu, displacement, force, expected;
  };
  const std::vector<Case> cases{
      {TestFmu("maxwell_nostate"), "x", "F", "canGetAndSetFMUstate"},
      {test::EditedFmu("spring", "", "", "run_no_binary.fmu", false), "x", "F",
       "binaries/linux64/spring.so is missing"},
      {TestFmu("spring"), "q1", "F", "no variable 'q1'"},
      {TestFmu("spring"), "x", "k", "variable 'k' has causality parameter"},
      {test::EditedFmu("spring", R"(<Unit name="m"><BaseUnit m="1"/></Unit>)",
                       R"(<Unit name="m"><BaseUnit s="1"/></Unit>)", "run_secs.fmu"),
       "x", "F", "variable 'x' (a slot displacement) has unit 'm'"},
      // Issue 45: bounded unpacking (a small zip bomb) and a variable declared twice.
      {test::FmuWith("spring", {{"resources/zeros.bin", std::string(8u << 20, '\0')}},
                     "run_zeros.fmu"),
       "x", "F", "the limit of the compression ratio is 200"},
      {test::EditedFmu("spring", R"(<ScalarVariable name="k")", R"(<ScalarVariable name="x")",
                       "run_twice.fmu"),
       "x", "F", "variable 'x' is declared twice"},
      // Issue 48: an FMI 3 array input is refused before the run (not at its first step).
      {test::EditedFmu("maxwell3", R"(unit="m"
        start="0"/>)", R"(unit="m" start="0 0 0"><Dimension start="3"/></Float64>)",
                       "run_array3.fmu"),
       "x", "F", "variable 'x' is an array [3]"}};
  for (const Case& c : cases) {
    test_support::WriteText(dir / "refused.yaml",
                            Config(kHeun, "substructures:\n  r1: {type: fmu, fmu: " + c.fmu +
                                              ", displacement: " + c.displacement +
                                              ", force: " + c.force + "}\n"));
    const auto [status, out] = testing::RunCommand(std::string(HYBRIDTEST_BINARY) + " run " +
                                                   (dir / "refused.yaml").string() + " --out " +
                                                   (dir / "n.csv").string());
    EXPECT_EQ(status, 2) << out;
    EXPECT_NE(out.find(c.fmu), std::string::npos) << out;
    EXPECT_NE(out.find(c.expected), std::string::npos) << out;
  }
}

}  // namespace
}  // namespace hybridtest::fmi
