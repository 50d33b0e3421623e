// An FMU as the plant of an emulated bench (fmi/fmu_plant.h): the spring FMU of examples/fmi/
// in place of the built-in emulated bench. The transfer system itself (forces, hold, sizes,
// its state), the run of examples/fmi/rotor-spring-plant.yaml against the same test on the
// built-in ideal emulated bench (the binary), `plan` over it, and its refusals (exit 2, naming
// the FMU file and the variable).
#include <gtest/gtest.h>

#include <cmath>
#include <csignal>
#include <fstream>
#include <sstream>

#include "hybridtest/common/error.h"
#include "hybridtest/fmi/fmu_plant.h"
#include "fmi/fmi_test_support.h"
#include "integration/child_process.h"
#include "integration/resume_support.h"
#include "support/temp_dir.h"

namespace hybridtest::testing {
namespace {

const std::string kSpring = std::string(HYBRIDTEST_EXAMPLE_FMU_DIR) + "/spring.fmu";

std::string Slurp(const fs::path& path) {
  std::ifstream in(path);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

void Replace(std::string& text, const std::string& from, const std::string& to) {
  const auto at = text.find(from);
  ASSERT_NE(at, std::string::npos) << from;
  text.replace(at, from.size(), to);
}

substructures::TransferSpec Plant(const std::string& yaml) {
  const YamlInput in = YamlInput::FromText(yaml, "test.yaml");
  return fmi::ParseFmuPlant(in, in.root(), "transfer", nullptr);
}

TEST(FmuPlant, ExecutesTheSpringHoldsAndKeepsItsTime) {
  auto transfer = Plant("{type: fmu, fmu: " + kSpring +
                        ", command: x, force: F, parameters: {k: 5000}, move_time: 0.01}")
                      .make();
  ASSERT_EQ(transfer->num_actuators(), 1);
  EXPECT_THROW(transfer::ExecuteOne(*transfer, 0.01), TransferError);  // not active yet
  transfer->Activate();
  const transfer::Measurement m = transfer::ExecuteOne(*transfer, 0.012);
  EXPECT_DOUBLE_EQ(m.force, 5000 * 0.012);
  EXPECT_DOUBLE_EQ(m.position, 0.012);  // no position output: the command
  EXPECT_NEAR(m.lab_time, 0.01, 1e-12);
  const auto state = transfer->SaveState();
  EXPECT_NEAR(transfer::ExecuteOne(*transfer, -0.002).lab_time, 0.02, 1e-12);
  transfer->Hold();
  EXPECT_THROW(transfer::ExecuteOne(*transfer, 0.0), TransferError);  // held: nothing moves
  std::vector<double> two{0.0, 0.0};
  std::vector<transfer::Measurement> out(2);
  transfer->Activate();
  EXPECT_THROW(transfer->Execute(two, out), TransferError);  // two commands for one actuator
  auto restored = Plant("{type: fmu, fmu: " + kSpring + ", command: x, force: F}").make();
  restored->RestoreState(state);
  restored->Activate();
  EXPECT_NEAR(transfer::ExecuteOne(*restored, 0.0).lab_time, 0.01 + 0.1, 1e-9);
}

// n actuators on the one seam: the coupled springs of tests/fmi/ as a two-actuator plant,
// f = K a, every command set before the one step.
TEST(FmuPlant, TwoActuatorsOnTheOneSeam) {
  auto transfer = Plant("{type: fmu, fmu: " + std::string(HYBRIDTEST_TEST_FMU_DIR) +
                        "/coupled_spring.fmu, command: [x1, x2], force: [F1, F2], "
                        "parameters: {k11: 1000, k12: 200, k21: 300, k22: 2000}}")
                      .make();
  ASSERT_EQ(transfer->num_actuators(), 2);
  transfer->Activate();
  const std::vector<double> a{0.01, -0.02};
  std::vector<transfer::Measurement> out(2);
  transfer->Execute(a, out);
  EXPECT_DOUBLE_EQ(out[0].force, 1000 * 0.01 + 200 * -0.02);
  EXPECT_DOUBLE_EQ(out[1].force, 300 * 0.01 + 2000 * -0.02);
  EXPECT_DOUBLE_EQ(out[1].position, -0.02);
  std::vector<transfer::Measurement> one(1);
  EXPECT_THROW(transfer->Execute(std::vector<double>{0.0}, one), TransferError);
}

// A position output: the Maxwell FMU of tests/fmi/ with its dashpot displacement y made an
// output, read as the measured position (y follows the command x with c/k = 6.9 ms).
TEST(FmuPlant, PositionOutputIsTheMeasuredPosition) {
  const std::string fmu = fmi::test::EditedFmu(
      "maxwell", R"(name="y" valueReference="5" causality="local")",
      R"(name="y" valueReference="5" causality="output")", "maxwell_y.fmu");
  auto transfer = Plant("{type: fmu, fmu: " + fmu + ", command: x, position: y, force: F, "
                        "parameters: {k: 7200, c: 50}, move_time: 0.01, step: 0.001}")
                      .make();
  transfer->Activate();
  const transfer::Measurement m = transfer::ExecuteOne(*transfer, 0.01);
  const double y = 0.01 * (1.0 - std::exp(-7200 * 0.01 / 50));  // exact over the 10 steps
  EXPECT_NEAR(m.position, y, 1e-12);
  EXPECT_NEAR(m.force, 7200 * (0.01 - y), 1e-9);
}

// examples/fmi/rotor-spring-plant.yaml (2 s) and the same test on the built-in emulated bench
// of examples/rotor/bench-ideal.yaml (p0 0): the same journal, q and r, within 1e-9.
TEST(FmuPlant, RunEqualsTheBuiltInEmulatedBench) {
  const fs::path dir = ResumeTestDir("fmu_plant");
  std::string text = Slurp(fs::path(kSource) / "examples/fmi/rotor-spring-plant.yaml");
  Replace(text, "../../build/release/examples/fmi/spring.fmu", kSpring);
  Replace(text, "duration: 10.0", "duration: 2.0");
  test_support::WriteText(dir / "fmu.yaml", text);
  std::string bench = Slurp(fs::path(kSource) / "examples/rotor/bench-ideal.yaml");
  Replace(bench, "p0_mm: 20", "p0_mm: 0");
  test_support::WriteText(dir / "ideal.yaml", bench);
  const auto at = text.find("      type: fmu");
  const auto end = text.find("    setup:");
  text.replace(at, end - at, "      type: emulated\n      config: ideal.yaml\n");
  test_support::WriteText(dir / "emulated.yaml", text);
  RunToEnd(RunArgs((dir / "fmu.yaml").string(), dir / "fmu.csv"), dir / "fmu.log");
  RunToEnd(RunArgs((dir / "emulated.yaml").string(), dir / "emulated.csv"), dir / "emulated.log");
  const auto a = ReadLines(dir / "fmu.csv");
  const auto b = ReadLines(dir / "emulated.csv");
  ASSERT_EQ(a.size(), b.size());
  ASSERT_EQ(a.size(), 2002u);
  double largest = 0.0, largest_force = 0.0, moved = 0.0;
  for (std::size_t i = 1; i < a.size(); ++i) {
    const auto x = SplitCsv(a[i]), y = SplitCsv(b[i]);
    for (int c = 1; c <= 4; ++c) largest = std::max(largest, std::abs(std::stod(x[c]) - std::stod(y[c])));
    largest_force = std::max(largest_force, std::abs(std::stod(x[9]) - std::stod(y[9])));
    moved = std::max(moved, std::abs(std::stod(x[1])));
  }
  EXPECT_LE(largest, 1e-9) << "q [m or rad]";
  EXPECT_LE(largest_force, 1e-6) << "r1 [N]";
  EXPECT_GT(moved, 1e-4);
  EXPECT_NE(Slurp(dir / "fmu.meta.json").find("spring.fmu"), std::string::npos)
      << "the FMU is a recorded run input";
}

// `plan` takes the FMU plant as an emulated bench (no steel): its candidates run on it.
TEST(FmuPlant, PlanRunsItsCandidatesOnThePlant) {
  const fs::path dir = ResumeTestDir("fmu_plant_plan");
  std::string text = Slurp(fs::path(kSource) / "examples/fmi/rotor-spring-plant.yaml");
  Replace(text, "../../build/release/examples/fmi/spring.fmu", kSpring);
  Replace(text, "duration: 10.0", "duration: 1.0");
  test_support::WriteText(dir / "plan.yaml", text);
  Child child(HybridtestArgv({"plan", (dir / "plan.yaml").string()}), dir / "plan.log");
  ASSERT_EQ(child.WaitExit(120.0), 0) << child.output();
  EXPECT_NE(child.output().find("as configured (runge-kutta heun, dt 0.001 s)            2001"),
            std::string::npos) << child.output();
  EXPECT_NE(child.output().find("recommended"), std::string::npos) << child.output();
}

// A real-time rehearsal (decision 0015) on the virtual clock: the FMU plant advances to the
// clock at every tick; the spring's force is k times the command on every committed row.
TEST(FmuPlant, PacedRunOnTheVirtualClock) {
  const fs::path dir = ResumeTestDir("fmu_plant_paced");
  std::string text = Slurp(fs::path(kSource) / "examples/real-time/rotor.yaml");
  const auto at = text.find("      type: rt_plant");
  const auto end = text.find("    setup:");
  ASSERT_NE(at, std::string::npos);
  text.replace(at, end - at, "      type: fmu\n      fmu: " + kSpring +
                                 "\n      command: x\n      force: F\n"
                                 "      parameters: {k: 7200}\n");
  Replace(text, "duration: 10.0", "duration: 0.5");
  test_support::WriteText(dir / "paced.yaml", text);
  RunToEnd({"run", (dir / "paced.yaml").string(), "--clock", "virtual", "--out",
            (dir / "paced.csv").string(), "--quiet"},
           dir / "paced.log");
  const auto lines = ReadLines(dir / "paced.csv");
  ASSERT_EQ(lines.size(), 502u);
  const auto header = SplitCsv(lines[0]);
  const auto column = [&](const std::string& name) {
    return std::find(header.begin(), header.end(), name) - header.begin();
  };
  const auto command = column("r1_command"), force = column("r1_force");
  ASSERT_LT(force, static_cast<long>(header.size()));
  double moved = 0.0;
  for (std::size_t i = 1; i < lines.size(); ++i) {
    const auto row = SplitCsv(lines[i]);
    EXPECT_NEAR(std::stod(row[force]), 7200 * std::stod(row[command]), 1e-9) << "row " << i;
    moved = std::max(moved, std::abs(std::stod(row[command])));
  }
  EXPECT_GT(moved, 1e-3);
}

// A plant with a state (the Bouc-Wen FMU of examples/fmi/, yielding): a run killed (SIGKILL)
// and resumed gives the uninterrupted journal, its serialized FMU state restored (lab times
// differ: the resume's re-imposition is a move).
TEST(FmuPlant, StatefulPlantKilledAndResumedEqualsUninterrupted) {
  const fs::path dir = ResumeTestDir("fmu_plant_resume");
  std::string text = Slurp(fs::path(kSource) / "examples/fmi/rotor-spring-plant.yaml");
  Replace(text, "../../build/release/examples/fmi/spring.fmu",
          std::string(HYBRIDTEST_EXAMPLE_FMU_DIR) + "/bouc_wen.fmu");
  Replace(text, "parameters: {k: 7200}", "parameters: {k: 7200, alpha: 0.5, x_y: 0.002, n: 2}");
  Replace(text, "duration: 10.0", "duration: 3.0");  // the wind alone yields the blade
  test_support::WriteText(dir / "bw.yaml", text);
  const std::string config = (dir / "bw.yaml").string();
  RunToEnd(RunArgs(config, dir / "whole.csv"), dir / "whole.log");
  const auto whole = ReadLines(dir / "whole.csv");
  ASSERT_EQ(whole.size(), 3002u);
  double elastic_gap = 0.0;  // the plant yielded: its force left k q (a state to restore)
  for (std::size_t i = 1; i < whole.size(); ++i) {
    const auto row = SplitCsv(whole[i]);
    elastic_gap = std::max(elastic_gap, std::abs(7200 * std::stod(row[1]) - std::stod(row[9])));
  }
  EXPECT_GT(elastic_gap, 1.0);
  const fs::path csv = dir / "killed.csv";
  if (!RunAndSignalAt(RunArgs(config, csv), csv, fs::file_size(dir / "whole.csv") / 2, SIGKILL,
                      dir / "run.log", 128 + SIGKILL)) {
    GTEST_SKIP() << "the run ended before the kill";
  }
  ASSERT_LT(ReadLines(csv).size(), whole.size());
  const auto [status, out] = Resume(csv, {"--quiet"}, dir / "resume.log");
  ASSERT_EQ(status, 0) << out;
  ExpectSameJournal(whole, ReadLines(csv), true);
}

TEST(FmuPlant, RefusalsExitTwoNamingTheFmuAndTheVariable) {
  const fs::path dir = ResumeTestDir("fmu_plant_refusals");
  const std::string base = Slurp(fs::path(kSource) / "examples/fmi/rotor-spring-plant.yaml");
  struct Case {
    std::string from, to, expected;
  };
  for (const Case& c : std::vector<Case>{
           {"command: x ", "command: u ", "no variable 'u'"},
           {"force: F ", "force: x ", "variable 'x' has causality input"},
           {"command: x ", "command: x\n      position: F ", "variable 'F'"}}) {
    std::string text = base;
    Replace(text, "../../build/release/examples/fmi/spring.fmu", kSpring);
    Replace(text, c.from, c.to);
    test_support::WriteText(dir / "bad.yaml", text);
    Child child(HybridtestArgv({"run", (dir / "bad.yaml").string(), "--out",
                                (dir / "bad.csv").string(), "--quiet"}),
                dir / "bad.log");
    EXPECT_EQ(child.WaitExit(60.0), 2) << child.output();
    EXPECT_NE(child.output().find(kSpring), std::string::npos) << child.output();
    EXPECT_NE(child.output().find(c.expected), std::string::npos) << child.output();
  }
}

}  // namespace
}  // namespace hybridtest::testing
