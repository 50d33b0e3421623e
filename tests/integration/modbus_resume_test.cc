// `hybridtest resume` over Modbus/TCP (issue 15, the Modbus contract): a run against the
// pymodbus controller is killed (SIGKILL) mid-way, the controller restarts with the actuator
// somewhere else (0 mm, 20 to 30 mm from the last committed command), and the resume
//   - reads the controller's position without moving (ModbusTransfer::Read),
//   - ramps back from that measured position in moves of at most max_increment (2 mm): no
//     command the controller receives differs from the previous one (or from where it
//     started) by more than max_increment,
//   - and ends with the journal of an uninterrupted run (every channel but the lab time);
// and a genuine but older run state, or one forged with its checksum recomputed, is refused
// before the controller receives any command (issue 33, item 4).
#include <gmock/gmock.h>

#include <algorithm>
#include <cmath>
#include <fstream>

#include "hybridtest/io/run_reader.h"
#include "hybridtest/runner/run_state.h"
#include "integration/resume_support.h"
#include "transfer/modbus_server_process.h"

namespace hybridtest::testing {
namespace {

constexpr double kMaxIncrementMm = 2.0;  // tests/data/resume-modbus.yaml, safety.max_increment

// The commands the controller received, in mm (its --log-commands file: "SEQUENCE MM" lines).
std::vector<double> ReceivedCommands(const fs::path& log) {
  std::ifstream in(log);
  std::vector<double> commands;
  long sequence = 0;
  double mm = 0.0;
  while (in >> sequence >> mm) commands.push_back(mm);
  return commands;
}

std::vector<std::string> Controller(const std::vector<std::string>& extra) {
  std::vector<std::string> args{"--stiffness", "7.2", "--p0-mm", "20"};
  args.insert(args.end(), extra.begin(), extra.end());
  return args;
}

TEST(ModbusResume, ControllerRestartedElsewhereIsRampedBackWithinMaxIncrement) {
  if (!PymodbusAvailable()) GTEST_SKIP() << kPymodbusMissing;
  const fs::path dir = ResumeTestDir("modbus");
  const std::string config = kSource + "/tests/data/resume-modbus.yaml";
  // The uninterrupted reference.
  const fs::path reference = dir / "reference.csv";
  {
    auto server = ModbusServerProcess::Pymodbus(Controller({}));
    ASSERT_EQ(RunToEnd(RunArgs(config, reference, server.address()), dir / "ref.log"), 0);
  }
  // The run, killed half-way; its controller goes away with it.
  const fs::path csv = dir / "killed.csv";
  {
    auto server = ModbusServerProcess::Pymodbus(Controller({}));
    ASSERT_TRUE(RunAndSignalAt(RunArgs(config, csv, server.address()), csv,
                               fs::file_size(reference) / 2, SIGKILL, dir / "run.log",
                               128 + SIGKILL));
  }
  // The controller restarts with the actuator at 0 mm and logs every command it receives.
  const fs::path log = dir / "commands.log";
  auto restarted =
      ModbusServerProcess::Pymodbus(Controller({"--start-mm", "0", "--log-commands", log.string()}));
  const auto [status, output] = Resume(csv, {"--bench", restarted.address()}, dir / "resume.log");
  ASSERT_EQ(status, 0) << output;
  ExpectSameJournal(ReadLines(reference), ReadLines(csv), true);

  // The resume read where the actuator was and ramped from there.
  const auto check = Sidecar(csv)["resumes"][0]["checks"][0];
  EXPECT_FALSE(check["read_position_m"].is_null()) << "the position was not read: " << check.dump();
  if (!check["read_position_m"].is_null()) {
    EXPECT_EQ(check["read_position_m"].get<double>(), 0.0);
  }
  const double committed_mm = check["command_m"].get<double>() * 1e3;
  ASSERT_GT(committed_mm, 10.0 * kMaxIncrementMm) << "the restart should be far from the commit";
  const long ramp_moves = check["ramp_moves"].get<long>();
  EXPECT_EQ(ramp_moves, static_cast<long>(std::ceil(committed_mm / kMaxIncrementMm)) - 1);
  // The stage record flags each ramp move (stage −2) and the one re-imposition (stage −1).
  const io::RunData stages = io::LoadRun((dir / "killed.stages.csv").string());
  const Eigen::VectorXd stage = stages.Get("stage");
  EXPECT_EQ((stage.array() == -2.0).count(), ramp_moves);
  EXPECT_EQ((stage.array() == -1.0).count(), 1);

  // Every command the restarted controller received: none more than max_increment from the
  // previous one, the first from where the actuator stood (0 mm). float32 on the wire rounds
  // a 20 mm command by at most 1e-6 mm.
  const std::vector<double> commands = ReceivedCommands(log);
  ASSERT_GT(commands.size(), static_cast<std::size_t>(ramp_moves + 1));
  ASSERT_GE(ramp_moves, 0);
  double previous = 0.0, largest = 0.0;
  for (std::size_t i = 0; i < commands.size(); ++i) {
    const double step = std::abs(commands[i] - previous);
    EXPECT_LE(step, kMaxIncrementMm + 1e-5) << "command " << i << ": " << previous << " mm → "
                                            << commands[i] << " mm";
    largest = std::max(largest, step);
    previous = commands[i];
  }
  RecordProperty("largest_command_step_mm", fmt::format("{:.6g}", largest));
  RecordProperty("ramp_moves", static_cast<int>(ramp_moves));
  std::cout << "[ resume over Modbus: " << ramp_moves << " ramp moves from 0 mm to "
            << committed_mm << " mm, " << commands.size()
            << " commands, largest step " << largest << " mm ]\n";
  // The ramp ends on the committed command (float32 on the wire).
  EXPECT_EQ(commands[static_cast<std::size_t>(ramp_moves)],
            static_cast<double>(static_cast<float>(committed_mm)));
  EXPECT_GT(largest, 0.9 * kMaxIncrementMm) << "the ramp should use most of the increment";
  fs::remove_all(dir);
}

TEST(ModbusResume, AnOlderOrForgedStateIsRefusedBeforeTheControllerReceivesACommand) {
  if (!PymodbusAvailable()) GTEST_SKIP() << kPymodbusMissing;
  const fs::path dir = ResumeTestDir("modbus_older");
  const std::string config = kSource + "/tests/data/resume-modbus.yaml";
  const fs::path csv = dir / "k.csv";
  const fs::path state = dir / "k.state.json";
  std::string early, late;
  {
    // Stopped with Ctrl-C twice (run, then resume) on one controller: an early and a late state.
    auto server = ModbusServerProcess::Pymodbus(Controller({}));
    ASSERT_TRUE(RunAndSignalAt(RunArgs(config, csv, server.address()), csv, 20000, SIGINT,
                               dir / "run.log", 130));
    early = test_support::ReadText(state);
    ASSERT_TRUE(RunAndSignalAt({"resume", csv.string(), "--quiet", "--bench", server.address()},
                               csv, fs::file_size(csv) + 20000, SIGINT, dir / "r1.log", 130));
    late = test_support::ReadText(state);
  }
  ASSERT_FALSE(early.empty());
  ASSERT_NE(early, late);
  const std::string journal = test_support::ReadText(csv);

  // A controller that logs every command it receives: each refused resume must leave it empty.
  const fs::path log = dir / "commands.log";
  auto controller = ModbusServerProcess::Pymodbus(Controller({"--log-commands", log.string()}));
  auto expect_refused = [&](const std::string& what) {
    const auto [status, out] = Resume(csv, {"--quiet", "--bench", controller.address()},
                                      dir / "refused.log");
    EXPECT_EQ(status, 2) << out;
    EXPECT_THAT(out, ::testing::HasSubstr(what));
    EXPECT_TRUE(ReceivedCommands(log).empty()) << "the controller received a command";
    EXPECT_EQ(test_support::ReadText(csv), journal);
  };
  // The early state put back: genuine (its checksum is right) but older than the journal.
  test_support::WriteText(state, early);
  expect_refused("is older than the journal");
  // The late state with a later step, its checksum recomputed.
  nlohmann::json forged = nlohmann::json::parse(late);
  forged["scheme"]["step"] = forged["scheme"]["step"].get<long>() + 1;
  forged["checksum"] = runner::RunStateChecksum(forged);
  test_support::WriteText(state, forged.dump());
  expect_refused("scheme.step");

  // The genuine late state resumes to the end on that controller.
  test_support::WriteText(state, late);
  const auto [status, out] = Resume(csv, {"--quiet", "--bench", controller.address()},
                                    dir / "r2.log");
  EXPECT_EQ(status, 0) << out;
  EXPECT_FALSE(ReceivedCommands(log).empty());
  fs::remove_all(dir);
}

}  // namespace
}  // namespace hybridtest::testing
