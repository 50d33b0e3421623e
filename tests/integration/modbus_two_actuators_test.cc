// Blade 1's tip on two actuators over Modbus/TCP (examples/06_blade_two_actuators/modbus.yaml)
// against the pymodbus controller serving both actuators on the coupled specimen K (float64
// registers, ideal actuators):
//   - the contract: q and u equal those of `hybridtest simulate` with the numerical substructure
//     of stiffness Tᵀ K T (dummy.yaml) within 1e-9 (absolute, SI), Heun at 1 ms over the
//     example's 10 s (20,001 exchanges, a few seconds against pymodbus), as the two-actuator bench
//     does in process and over TCP (tests/runner/multi_actuator_session_test.cc);
//   - a fault on actuator 2 stops `hybridtest run` (exit status 4) naming the actuator, with
//     both hold coils set in the controller;
//   - a run killed (SIGKILL) and resumed against a restarted controller re-imposes both
//     actuators' committed commands and ends with the journal of an uninterrupted run.
// Skipped, with a message, when python3-pymodbus is not installed.
#include <fmt/format.h>
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <sstream>

#include "hybridtest/io/run_reader.h"
#include "hybridtest/io/run_spec_yaml.h"
#include "hybridtest/runner/session.h"
#include "hybridtest/transfer/modbus/modbus_transfer.h"
#include "integration/resume_support.h"
#include "transfer/modbus_server_process.h"

namespace hybridtest::testing {
namespace {

const std::string kExample = kSource + "/examples/06_blade_two_actuators/";

// The test controller of the example's comment: K = [[5, 1.2], [1.2, 3]] N/mm in actuator
// coordinates (bench-2act.yaml's [[5000, 1200], [1200, 3000]] N/m), zero force at 20 and 30 mm.
std::vector<std::string> Controller(const std::vector<std::string>& extra = {}) {
  std::vector<std::string> args{"--actuators", "2", "--type", "float64", "--stiffness-matrix",
                                "5,1.2;1.2,3", "--p0-mm", "20,30"};
  args.insert(args.end(), extra.begin(), extra.end());
  return args;
}

// Every committed row's [q; u].
class StateRecorder final : public runner::SessionObserver {
 public:
  void OnCommit(const runner::CommitEvent& e) override {
    if (e.kind == runner::RowKind::kCommitted) rows.emplace_back(e.x.begin(), e.x.end());
  }
  std::vector<std::vector<double>> rows;
};

std::vector<std::vector<double>> RunInMemory(const std::string& config, double duration,
                                             const std::string& bench = "") {
  io::SubstructureOptions options;
  if (!bench.empty()) options.bench_address = bench;
  io::RunSpec spec = io::LoadRunSpec(config, options);
  spec.output.files = false;
  spec.quiet = true;
  spec.scheme.steps = static_cast<long>(std::lround(duration / 0.001));
  spec.scheme.duration = duration;
  runner::Session session(std::move(spec));
  StateRecorder recorder;
  session.AddObserver(recorder);
  const runner::StepResult r = session.Run();
  EXPECT_EQ(r.status, runner::SessionStatus::kFinished) << r.reason;
  return recorder.rows;
}

// The example with its model file named absolutely, a shorter duration, written to `dir`.
fs::path ShortExample(const fs::path& dir, const std::string& duration) {
  std::ifstream in(kExample + "modbus.yaml");
  std::stringstream text;
  text << in.rdbuf();
  std::string yaml = text.str();
  const auto replace = [&](const std::string& from, const std::string& to) {
    const auto at = yaml.find(from);
    ASSERT_NE(at, std::string::npos) << from;
    yaml.replace(at, from.size(), to);
  };
  replace("file: blade_tip.yaml", "file: " + kExample + "blade_tip.yaml");
  replace("duration: 10.0", "duration: " + duration);
  const fs::path path = dir / "modbus.yaml";
  std::ofstream(path) << yaml;
  return path;
}

// Each actuator's status as the controller reports it now, read by another client.
std::string ControllerStatus(const ModbusServerProcess& server) {
  transfer::modbus::ModbusOptions o;
  o.port = server.port();
  transfer::modbus::RegisterMap a;
  a.command.type = a.position.type = a.force.type = transfer::modbus::ValueType::kFloat64;
  a.sequence.address = 4;
  a.force.address = 4;
  a.ack.address = 8;
  a.status->address = 9;
  o.maps = {a, transfer::modbus::StridedMap(a, {5, 10, 2}, 1)};
  transfer::modbus::ModbusTransfer observer(o);
  return observer.Probe()->status;
}

TEST(ModbusTwoActuatorRun, ContractTheSlotsSeeTheTransformedStiffnessWithin1e9) {
  if (!PymodbusAvailable()) GTEST_SKIP() << kPymodbusMissing;
  auto server = ModbusServerProcess::Pymodbus(Controller());
  const double duration = 10.0;  // 20,001 exchanges
  const auto physical = RunInMemory(kExample + "modbus.yaml", duration, server.address());
  const auto numerical = RunInMemory(kExample + "dummy.yaml", duration);
  ASSERT_EQ(physical.size(), 10001u);
  ASSERT_EQ(numerical.size(), physical.size());
  double worst = 0.0, peak_flap = 0.0, peak_edge = 0.0;
  for (std::size_t i = 0; i < physical.size(); ++i) {
    ASSERT_EQ(physical[i].size(), 4u);  // q_flap, q_edge, u1, u2
    for (std::size_t j = 0; j < 4; ++j) {
      worst = std::max(worst, std::abs(physical[i][j] - numerical[i][j]));
    }
    peak_flap = std::max(peak_flap, std::abs(numerical[i][0]));
    peak_edge = std::max(peak_edge, std::abs(numerical[i][1]));
  }
  RecordProperty("max_difference_q_u", fmt::format("{:.3g}", worst));
  std::cout << "[ two actuators over Modbus: largest |Δq|, |Δu| against dummy.yaml " << worst
            << " (SI) over " << physical.size() << " rows ]\n";
  EXPECT_LT(worst, 1e-9);
  EXPECT_GT(peak_flap, 1e-3) << "too little motion to test anything";
  EXPECT_GT(peak_edge, 1e-4) << "too little motion to test anything";
}

TEST(ModbusTwoActuatorRun, AFaultOnActuator2StopsTheRunWithBothActuatorsHolding) {
  if (!PymodbusAvailable()) GTEST_SKIP() << kPymodbusMissing;
  const fs::path dir = ResumeTestDir("modbus-2act-fault");
  const fs::path config = ShortExample(dir, "0.2");
  // Command 101 of actuator 2: the first stage of the step from t = 0.050 s (Heun, with the
  // initial evaluation as command 1).
  auto server = ModbusServerProcess::Pymodbus(Controller({"--fault", "fault@101/2"}));
  const fs::path csv = dir / "fault.csv";
  Child child(HybridtestArgv(RunArgs(config.string(), csv, server.address())), dir / "run.log");
  const int status = child.WaitExit(120.0);
  const std::string output = child.output();
  EXPECT_EQ(status, 4) << output;
  EXPECT_NE(output.find("actuator 2 reports a fault (status bit 1)"), std::string::npos) << output;
  EXPECT_NE(output.find("blade1"), std::string::npos) << output;
  const io::RunData data = io::LoadRun(csv.string());
  EXPECT_EQ(data.num_rows(), 51);
  EXPECT_EQ(data.metadata.at("status").get<std::string>().rfind("stopped", 0), 0u);
  // Both hold coils are set: each actuator reports holding, actuator 2 with its fault.
  const std::string state = ControllerStatus(server);
  EXPECT_NE(state.find("status 0x0005: no fault, enabled, holding; actuator 2"), std::string::npos)
      << state;
  EXPECT_NE(state.find("status 0x0007: FAULT, enabled, holding"), std::string::npos) << state;
  fs::remove_all(dir);
}

// The commands a controller received ("SEQUENCE MM ACTUATOR" lines): per actuator, in mm.
std::vector<std::vector<double>> ReceivedCommands(const fs::path& log) {
  std::ifstream in(log);
  std::vector<std::vector<double>> commands(2);
  long sequence = 0;
  double mm = 0.0;
  int actuator = 0;
  while (in >> sequence >> mm >> actuator) commands.at(static_cast<std::size_t>(actuator - 1)).push_back(mm);
  return commands;
}

TEST(ModbusTwoActuatorRun, KilledAndResumedRunReimposesBothActuators) {
  if (!PymodbusAvailable()) GTEST_SKIP() << kPymodbusMissing;
  const fs::path dir = ResumeTestDir("modbus-2act");
  const std::string config = ShortExample(dir, "1.0").string();
  const fs::path reference = dir / "reference.csv";
  {
    auto server = ModbusServerProcess::Pymodbus(Controller());
    ASSERT_EQ(RunToEnd(RunArgs(config, reference, server.address()), dir / "ref.log"), 0);
  }
  const fs::path csv = dir / "killed.csv";
  {
    auto server = ModbusServerProcess::Pymodbus(Controller());
    ASSERT_TRUE(RunAndSignalAt(RunArgs(config, csv, server.address()), csv,
                               fs::file_size(reference) / 2, SIGKILL, dir / "run.log",
                               128 + SIGKILL));
  }
  // The controller restarts with both actuators at zero specimen force (20 and 30 mm).
  const fs::path log = dir / "commands.log";
  auto restarted = ModbusServerProcess::Pymodbus(Controller({"--log-commands", log.string()}));
  const auto [status, output] = Resume(csv, {"--bench", restarted.address()}, dir / "resume.log");
  ASSERT_EQ(status, 0) << output;
  ExpectSameJournal(ReadLines(reference), ReadLines(csv), true);
  EXPECT_EQ(Sidecar(csv)["status"], "completed");
  // The controller came back at 20 and 30 mm, away from the committed commands: resume read
  // both actuators there, walked them back together in moves within max_increment (2 mm;
  // stage −2), then re-imposed both committed commands in one write (stage −1) and went on.
  const nlohmann::json sidecar = Sidecar(csv);
  const long k = sidecar["resumes"][0]["step"].get<long>();
  const auto& checks = sidecar["resumes"][0]["checks"];
  ASSERT_EQ(checks.size(), 2U) << checks;
  const long ramps = checks[0]["ramp_moves"].get<long>();
  EXPECT_GT(ramps, 0) << checks;
  const io::RunData journal = io::LoadRun(csv.string());
  const auto received = ReceivedCommands(log);
  const char* channels[] = {"blade1_a1_command", "blade1_a2_command"};
  const double restart_mm[] = {20.0, 30.0};
  for (std::size_t a = 0; a < 2; ++a) {
    EXPECT_NEAR(checks[a]["read_position_m"].get<double>(), restart_mm[a] * 1e-3, 1e-12);
    ASSERT_GT(received[a].size(), static_cast<std::size_t>(ramps)) << channels[a];
    double from = restart_mm[a];
    for (long j = 0; j <= ramps; ++j) {
      EXPECT_LT(std::abs(received[a][static_cast<std::size_t>(j)] - from), 2.0)
          << channels[a] << " move " << j;
      from = received[a][static_cast<std::size_t>(j)];
    }
    EXPECT_NEAR(received[a][static_cast<std::size_t>(ramps)] * 1e-3,
                journal.Get(channels[a])(k), 1e-15) << channels[a];
  }
  EXPECT_EQ(received[0].size(), received[1].size());
  const io::RunData stages =
      io::LoadRun((csv.parent_path() / (csv.stem().string() + ".stages.csv")).string());
  EXPECT_EQ((stages.Get("stage").array() == -1.0).count(), 1);
  EXPECT_EQ((stages.Get("stage").array() == -2.0).count(), ramps);
  std::cout << "[ resume over Modbus, two actuators: from step " << k << ", "
            << received[0].size() << " commands per actuator ]\n";
  fs::remove_all(dir);
}

}  // namespace
}  // namespace hybridtest::testing
