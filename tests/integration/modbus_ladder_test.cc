// The hybrid test over Modbus/TCP, running the real `hybridtest` binary:
//   - ladder rung: the ideal bench played by the pymodbus controller equals the in-process
//     ideal emulated bench (ladder-emulated-ideal.yaml) within float32 resolution;
//   - a controller fault ends the run with exit status 4, a message naming the controller,
//     and every committed step in the journal; so does a controller that reports holding
//     mid-run; a measured position 50 mm off the command is a following-error safety stop
//     (exit status 3);
//   - the contract of issue 11: examples/rotor/modbus.yaml against a controller with the
//     default profile (ideal actuator, 5.25 N/mm, zero force at 0 mm) gives 10,001 rows with
//     q1..q3 within 1e-6 m of `simulate` with blade1.k_b = 5250. The 20,000 round trips run
//     against the libmodbus controller (bench/modbus/), which takes about a second; the
//     pymodbus one would take over a minute.
#include <fmt/format.h>
#include <gtest/gtest.h>
#include <unistd.h>

#include <sys/wait.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <string>

#include "hybridtest/io/run_reader.h"
#include "transfer/modbus_server_process.h"
#include "support/temp_dir.h"
#include "support/run_command.h"

namespace hybridtest {
namespace {

namespace fs = std::filesystem;
using testing::ModbusServerProcess;

const std::string kSource = HYBRIDTEST_SOURCE_DIR;
const std::string kBinary = HYBRIDTEST_BINARY;

// One directory per test process, made on first use.
fs::path OutDir() {
  static const fs::path dir = test_support::FreshTempDir("modbus");
  return dir;
}

// `hybridtest ARGS --quiet --out DIR/NAME.csv`, bounded by 600 s (a loaded CI machine makes
// every loopback round trip wait for a time slice): exit status, output, csv path.
struct CliRun {
  int status = 0;
  std::string output, csv;
};
CliRun Hybridtest(const std::string& name, const std::string& args) {
  CliRun r;
  r.csv = (OutDir() / (name + ".csv")).string();
  std::tie(r.status, r.output) =
      testing::RunCommand(fmt::format("{} {} --quiet --out {}", kBinary, args, r.csv), 600);
  return r;
}

// Largest |a − b| over channel `name` in the first `rows` rows.
double MaxDifference(const io::RunData& a, const io::RunData& b, const std::string& name,
                     long rows) {
  return (a.Get(name).head(rows) - b.Get(name).head(rows)).cwiseAbs().maxCoeff();
}

TEST(ModbusLadder, IdealControllerEqualsTheInProcessIdealBenchWithinFloat32) {
  if (!testing::PymodbusAvailable()) GTEST_SKIP() << testing::kPymodbusMissing;
  auto server = ModbusServerProcess::Pymodbus({"--stiffness", "7.2", "--p0-mm", "20"});
  const CliRun modbus = Hybridtest(
      "ladder_modbus",
      fmt::format("run {}/tests/data/ladder-modbus.yaml --bench {}", kSource, server.address()));
  ASSERT_EQ(modbus.status, 0) << modbus.output;
  const CliRun in_process =
      Hybridtest("ladder_emulated", "run " + kSource + "/tests/data/ladder-emulated-ideal.yaml");
  ASSERT_EQ(in_process.status, 0) << in_process.output;
  const io::RunData a = io::LoadRun(modbus.csv), b = io::LoadRun(in_process.csv);
  ASSERT_EQ(a.num_rows(), 501);
  const long rows = a.num_rows();
  EXPECT_EQ(a.metadata.at("status"), "completed");
  EXPECT_EQ(a.metadata.at("statistics").at("physical_evaluations"), 1001);
  // The commands are identical doubles until the first difference in r1 feeds back.
  // Float32 resolution: the command (~20 mm) is rounded once, to 2^-24 relative, and the force
  // once more: |Δr1| ≤ k·|c|·2^-24 + |F|·2^-24 with k = 7.2 N/mm, |c| ≤ 30 mm, |F| ≤ 100 N.
  const double eps = std::ldexp(1.0, -24);
  const double r_bound = 7.2 * 30.0 * eps + 100.0 * eps;  // [N], about 1.9e-5 N
  EXPECT_LT(MaxDifference(a, b, "r1", rows), r_bound);
  EXPECT_GT(MaxDifference(a, b, "r1", rows), 0.0) << "float32 should leave a trace";
  // A force error of δ N moves the 2 kg tip by at most δ/k_b in statics: 2.6e-9 m per 1.9e-5 N.
  for (const char* q : {"q1", "q2", "q3", "q4"}) {
    EXPECT_LT(MaxDifference(a, b, q, rows), r_bound / 7200.0) << q;
  }
  // The measured position came back through float32 (mm on the wire, m in the journal).
  const Eigen::VectorXd command = a.Get("r1_command"), position = a.Get("r1_position");
  EXPECT_LT((command - position).cwiseAbs().maxCoeff(), 0.030 * eps);
  EXPECT_GT(a.Get("q1").cwiseAbs().maxCoeff(), 1e-4) << "too little motion to test anything";
  // Lab time is the wall time since Activate: positive and increasing.
  const Eigen::VectorXd lab = a.Get("r1_lab_time");
  EXPECT_GT(lab(rows - 1), lab(1));
}

TEST(ModbusLadder, ControllerFaultStopsTheRunWithExitStatus4) {
  if (!testing::PymodbusAvailable()) GTEST_SKIP() << testing::kPymodbusMissing;
  auto server = ModbusServerProcess::Pymodbus({"--p0-mm", "20", "--fault", "fault@101"});
  const CliRun run = Hybridtest(
      "fault_bit",
      fmt::format("run {}/tests/data/faults-modbus.yaml --bench {}", kSource, server.address()));
  EXPECT_EQ(run.status, 4) << run.output;
  EXPECT_NE(run.output.find("reports a fault (status bit 1)"), std::string::npos) << run.output;
  EXPECT_NE(run.output.find(server.address()), std::string::npos) << run.output;
  // Command 1 is the initial row's evaluation, then two per step (Heun): command 101 is the
  // first stage of the step that starts at t = 0.050 s, so rows t = 0..0.050 s (51) are
  // committed, and the stop is recorded in the sidecar.
  const io::RunData data = io::LoadRun(run.csv);
  EXPECT_EQ(data.num_rows(), 51);
  EXPECT_EQ(data.metadata.at("status").get<std::string>().rfind("stopped", 0), 0u);
}

TEST(ModbusLadder, ControllerReportingHoldingMidRunStopsTheRunWithExitStatus4) {
  if (!testing::PymodbusAvailable()) GTEST_SKIP() << testing::kPymodbusMissing;
  // The controller acknowledges command 101 but reports holding from then on.
  auto server = ModbusServerProcess::Pymodbus({"--p0-mm", "20", "--fault", "holding@101"});
  const CliRun run = Hybridtest(
      "holding_bit",
      fmt::format("run {}/tests/data/faults-modbus.yaml --bench {}", kSource, server.address()));
  EXPECT_EQ(run.status, 4) << run.output;
  EXPECT_NE(run.output.find("reports holding (status bit 2)"), std::string::npos) << run.output;
  const io::RunData data = io::LoadRun(run.csv);
  EXPECT_EQ(data.num_rows(), 51);  // as for the fault bit: the step of command 101 is not kept
  EXPECT_EQ(data.metadata.at("status").get<std::string>().rfind("stopped", 0), 0u);
}

TEST(ModbusLadder, MeasuredPosition50MmOffTheCommandIsAFollowingErrorSafetyStop) {
  if (!testing::PymodbusAvailable()) GTEST_SKIP() << testing::kPymodbusMissing;
  auto server = ModbusServerProcess::Pymodbus(
      {"--p0-mm", "20", "--fault", "offset@101", "--offset-mm", "50"});
  const CliRun run = Hybridtest(
      "following_error",
      fmt::format("run {}/tests/data/faults-modbus.yaml --bench {}", kSource, server.address()));
  EXPECT_EQ(run.status, 3) << run.output;  // a safety stop
  // The default limit is four settling windows, 0.2 mm; the message names both positions.
  EXPECT_NE(run.output.find("following_error violated"), std::string::npos) << run.output;
  EXPECT_NE(run.output.find("> following_error 0.2 mm"), std::string::npos) << run.output;
  EXPECT_NE(run.output.find("measured position 7"), std::string::npos) << run.output;  // ~70 mm
  const io::RunData data = io::LoadRun(run.csv);
  EXPECT_EQ(data.num_rows(), 51);
  EXPECT_NE(data.metadata.at("status").get<std::string>().find("following_error"),
            std::string::npos) << data.metadata.at("status");
}

TEST(ModbusLadder, ContractExampleEqualsTheSimulationWithTheSpecimenStiffness) {
#ifndef HYBRIDTEST_MODBUS_SERVER
  GTEST_SKIP() << "the libmodbus controller (bench/) is not built: HYBRIDTEST_BUILD_BENCH=OFF";
#else
  ModbusServerProcess server(
      {HYBRIDTEST_MODBUS_SERVER, "--listen", "127.0.0.1:0", "--stiffness", "5.25", "--p0-mm", "0"});
  const CliRun run = Hybridtest("contract", fmt::format("run {}/examples/rotor/modbus.yaml --bench {}",
                                                     kSource, server.address()));
  ASSERT_EQ(run.status, 0) << run.output;
  const CliRun reference =
      Hybridtest("contract_reference", "simulate " + kSource + "/tests/data/modbus-contract-simulate.yaml");
  ASSERT_EQ(reference.status, 0) << reference.output;
  const io::RunData a = io::LoadRun(run.csv), b = io::LoadRun(reference.csv);
  ASSERT_EQ(a.num_rows(), 10001);
  ASSERT_EQ(b.num_rows(), 10001);
  for (const char* q : {"q1", "q2", "q3"}) {
    const double worst = MaxDifference(a, b, q, a.num_rows());
    RecordProperty(std::string(q) + "_max_difference_m", fmt::format("{:.3g}", worst));
    EXPECT_LT(worst, 1e-6) << q;
  }
  EXPECT_EQ(a.metadata.at("statistics").at("physical_evaluations"), 20001);
#endif
}

}  // namespace
}  // namespace hybridtest
