// Fault tests of `hybridtest run` against `hybridtest bench` on 127.0.0.1 (a real server in
// another process, with test faults injected). Each fault must end in a safe hold, a clear
// error naming the cause, a non-zero exit status (3 safety stop, 4 transfer error), and a
// journal holding every committed step: rows 0..k, consecutive, parseable, and a sidecar whose
// status is "stopped: ...". Every wait is bounded.
#include <fcntl.h>
#include <fmt/format.h>
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "hybridtest/io/run_reader.h"
#include "integration/bench_process.h"
#include "integration/child_process.h"
#include "support/temp_dir.h"

namespace hybridtest {
namespace {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

const std::string kSource = HYBRIDTEST_SOURCE_DIR;
const std::string kIdealBench = kSource + "/examples/rotor/bench-ideal.yaml";
const std::string kFaultsConfig = kSource + "/tests/data/faults-remote.yaml";
constexpr int kSafetyStatus = 3;
constexpr int kTransferStatus = 4;

// One directory per test process, made on first use.
fs::path OutDir() {
  static const fs::path dir = test_support::FreshTempDir("faults");
  return dir;
}

// Starts `hybridtest bench` with its stderr (the event log) going to `log`.
std::unique_ptr<testing::BenchProcess> StartBench(const std::vector<std::string>& args,
                                                  const fs::path& log) {
  const int fd = ::open(log.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
  const int saved = ::dup(STDERR_FILENO);
  ::dup2(fd, STDERR_FILENO);  // inherited by the child forked in BenchProcess
  std::unique_ptr<testing::BenchProcess> bench;
  try {
    bench = std::make_unique<testing::BenchProcess>(args);
  } catch (...) {
    ::dup2(saved, STDERR_FILENO);
    ::close(saved);
    ::close(fd);
    throw;
  }
  ::dup2(saved, STDERR_FILENO);
  ::close(saved);
  ::close(fd);
  return bench;
}

struct FaultRun {
  int status = 0;
  double seconds = 0.0;  // wall time of `run`
  std::string output;    // its stdout and stderr
  std::string bench_log; // the bench's event log
  std::string csv;
};

// Runs `hybridtest run CONFIG --bench ... --out ...` against a bench with `bench_args`
// (with --quiet unless `quiet` is false: then the output has the progress lines).
FaultRun RunAgainstBench(const std::string& name, const std::vector<std::string>& bench_args,
                         const std::string& config = kFaultsConfig, double limit = 30.0,
                         bool quiet = true) {
  const fs::path log = OutDir() / (name + ".bench.log");
  std::vector<std::string> args = {"--config", kIdealBench};
  args.insert(args.end(), bench_args.begin(), bench_args.end());
  auto bench = StartBench(args, log);
  FaultRun r;
  r.csv = (OutDir() / (name + ".csv")).string();
  const auto start = Clock::now();
  {
    std::vector<std::string> command = {HYBRIDTEST_BINARY, "run", config, "--bench",
                                        fmt::format("127.0.0.1:{}", bench->port()), "--out",
                                        r.csv};
    if (quiet) command.push_back("--quiet");
    Child run(command, OutDir() / (name + ".out"));
    r.status = run.WaitExit(limit);
    r.seconds = std::chrono::duration<double>(Clock::now() - start).count();
    r.output = run.output();
  }
  // Wait (bounded) for the bench to log that it holds, then stop it (SIGTERM, reaped by its
  // destructor): a stop by the runner sends HOLD; a transfer error closes the connection.
  const auto deadline = Clock::now() + std::chrono::seconds(5);
  while (Clock::now() < deadline && ReadText(log).find("holding: client") == std::string::npos) {
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  bench.reset();
  r.bench_log = ReadText(log);
  return r;
}

// Every committed step is present: rows 0..k consecutive in t and parseable, the sidecar says
// "stopped: ..." and its statistics agree. Returns the run.
io::RunData ExpectCommittedRows(const FaultRun& r, long expected_rows) {
  const io::RunData run = io::LoadRun(r.csv);
  EXPECT_TRUE(run.warnings.empty()) << run.warnings.front();
  if (expected_rows >= 0) {
    EXPECT_EQ(run.num_rows(), expected_rows);
  }
  EXPECT_GE(run.num_rows(), 1);
  const Eigen::VectorXd t = run.Get("t");
  for (long i = 0; i < run.num_rows(); ++i) {
    EXPECT_NEAR(t(i), 1e-3 * static_cast<double>(i), 1e-12) << "row " << i;
  }
  // Every row but possibly the last (whose trial may have failed) is a complete measurement.
  for (long i = 0; i + 1 < run.num_rows(); ++i) {
    if (!std::isfinite(run.Get("r1")(i))) {
      ADD_FAILURE() << "row " << i << " has a non-finite r1";
      break;
    }
  }
  const std::string status = run.metadata.at("status");
  EXPECT_EQ(status.rfind("stopped: ", 0), 0u) << status;
  EXPECT_EQ(run.metadata.at("statistics").at("rows"), run.num_rows());
  return run;
}

void ExpectContains(const std::string& text, const std::string& part) {
  EXPECT_NE(text.find(part), std::string::npos) << "expected '" << part << "' in:\n" << text;
}

// Rows after a stop at command N (1-based): the command belongs to step (N−1)/2 (Heun: two
// stages), whose row exists; a stage-0 failure leaves it with NaN forces.
long RowsForCommand(long n) { return (n - 1) / 2 + 1; }

TEST(RunFaults, BenchKilledMidRun) {
  const fs::path log = OutDir() / "killed.bench.log";
  auto bench = StartBench({"--config", kIdealBench}, log);
  const std::string csv = (OutDir() / "killed.csv").string();
  Child run({HYBRIDTEST_BINARY, "run", kSource + "/examples/rotor/remote.yaml", "--quiet",
             "--bench", fmt::format("127.0.0.1:{}", bench->port()), "--out", csv},
            OutDir() / "killed.out");
  // Wait (bounded) until the run has committed some steps, then kill the bench outright.
  const auto deadline = Clock::now() + std::chrono::seconds(30);
  long rows = 0;
  while (Clock::now() < deadline && rows < 50) {
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
    std::ifstream in(csv);
    rows = -1;
    for (std::string line; std::getline(in, line);) ++rows;
  }
  ASSERT_GE(rows, 50) << "the run did not start";
  bench->Signal(SIGKILL);
  const auto killed = Clock::now();
  const int status = run.WaitExit(10.0);
  const double seconds = std::chrono::duration<double>(Clock::now() - killed).count();
  ASSERT_NE(status, -2) << "run did not exit within 10 s of the bench's death";
  EXPECT_EQ(status, kTransferStatus) << run.output();
  EXPECT_LT(seconds, 10.0);
  RecordProperty("exit_seconds", fmt::format("{:.3f}", seconds));
  ExpectContains(run.output(), "connection to the bench at 127.0.0.1:");
  ExpectContains(run.output(), "was lost");
  FaultRun r;
  r.csv = csv;
  const io::RunData data = ExpectCommittedRows(r, -1);
  EXPECT_GE(data.num_rows(), 50);
  EXPECT_LT(data.num_rows(), 10001) << "the run finished although its bench was killed";
  EXPECT_EQ(data.metadata.at("statistics").at("stop").at("kind"), "transfer");
}

TEST(RunFaults, NanForceIsASafetyStopNamingTheStep) {
  constexpr long kAt = 101;  // command 101 = step 50, stage 0
  const FaultRun r = RunAgainstBench("nan", {"--inject", fmt::format("nan@{}", kAt)});
  EXPECT_EQ(r.status, kSafetyStatus) << r.output;
  ExpectContains(r.output, "safety stop: force_finite violated at step 50 stage 0");
  ExpectContains(r.output, "not finite");
  const io::RunData run = ExpectCommittedRows(r, RowsForCommand(kAt));
  EXPECT_TRUE(std::isnan(run.Get("r1")(run.num_rows() - 1)));
  const auto& stop = run.metadata.at("statistics").at("stop");
  EXPECT_EQ(stop.at("limit"), "force_finite");
  EXPECT_EQ(stop.at("step"), 50);
  ExpectContains(r.bench_log, "holding: client asked for HOLD");
}

// Issue 50: the last progress line of a failed run said "done".
TEST(RunFaults, TheLastProgressLineOfAFailedRunTellsItsFailure) {
  const FaultRun r = RunAgainstBench("progress_failure", {"--inject", "nan@20"}, kFaultsConfig,
                                     30.0, false);
  EXPECT_NE(r.status, 0) << r.output;
  const std::size_t last = r.output.rfind("progress ");
  ASSERT_NE(last, std::string::npos) << r.output;
  const std::string line = r.output.substr(last, r.output.find('\n', last) - last);
  EXPECT_NE(line.find("| stopped: "), std::string::npos) << line;
  EXPECT_EQ(line.find("done"), std::string::npos) << line;
}

TEST(RunFaults, ForceSpikeHitsTheHardForceLimit) {
  constexpr long kAt = 400;  // command 400 = step 199, stage 1
  const FaultRun r = RunAgainstBench("spike", {"--inject", fmt::format("spike@{}", kAt)},
                                     kSource + "/tests/data/faults-remote-force.yaml");
  EXPECT_EQ(r.status, kSafetyStatus) << r.output;
  ExpectContains(r.output, "safety stop: force_hard violated at step 199 stage 1");
  const io::RunData run = ExpectCommittedRows(r, RowsForCommand(kAt));
  EXPECT_TRUE(std::isfinite(run.Get("r1")(run.num_rows() - 1)));  // stage 1: row 199 complete
  EXPECT_EQ(run.metadata.at("statistics").at("stop").at("limit"), "force_hard");
  ExpectContains(r.bench_log, "holding: client asked for HOLD");
}

TEST(RunFaults, StrokeLimitCommandIsNeverSent) {
  const FaultRun r = RunAgainstBench("stroke", {}, kSource + "/tests/data/faults-remote-stroke.yaml");
  EXPECT_EQ(r.status, kSafetyStatus) << r.output;
  ExpectContains(r.output, "safety stop: stroke_max violated");
  ExpectContains(r.output, "was not sent");
  const io::RunData run = ExpectCommittedRows(r, -1);
  const auto& stop = run.metadata.at("statistics").at("stop");
  EXPECT_EQ(stop.at("limit"), "stroke_max");
  const double stroke_max = stop.at("limit_value").get<double>();
  EXPECT_GT(stop.at("value").get<double>(), stroke_max);
  // Every command the bench executed (the stage record) is within the stroke, and the last
  // one recorded before the stop is the last one sent.
  const fs::path stages_csv = fs::path(r.csv).replace_extension("").string() + ".stages.csv";
  const io::RunData stages = io::LoadRun(stages_csv.string());
  ASSERT_GT(stages.num_rows(), 0);
  EXPECT_LE(stages.Get("r1_command").maxCoeff(), stroke_max);
  const long steps = run.metadata.at("statistics").at("steps");
  const long exchanges = stages.num_rows();
  EXPECT_EQ(exchanges, run.metadata.at("statistics").at("physical_evaluations").get<long>());
  EXPECT_EQ(stop.at("step").get<long>(), steps);
  // The stop report's history ends with the last command sent, answered, as recorded.
  ASSERT_FALSE(stop.at("history").empty());
  const auto& last = stop.at("history").back();
  EXPECT_TRUE(last.at("answered").get<bool>());
  EXPECT_EQ(last.at("command").get<double>(), stages.Get("r1_command")(exchanges - 1));
  ExpectContains(r.bench_log, "holding: client asked for HOLD");
}

TEST(RunFaults, CorruptedFrameNamesTheCrc) {
  const FaultRun r = RunAgainstBench("corrupt", {"--inject", "corrupt@60"});
  EXPECT_EQ(r.status, kTransferStatus) << r.output;
  ExpectContains(r.output, "corrupted frame");
  ExpectContains(r.output, "CRC mismatch");
  ExpectCommittedRows(r, RowsForCommand(60));
  ExpectContains(r.bench_log, "holding: client disconnected");
}

TEST(RunFaults, StaleSequenceNumberIsRefused) {
  const FaultRun r = RunAgainstBench("stale", {"--inject", "stale_seq@60"});
  EXPECT_EQ(r.status, kTransferStatus) << r.output;
  ExpectContains(r.output, "stale or duplicate sequence number");
  ExpectCommittedRows(r, RowsForCommand(60));
  ExpectContains(r.bench_log, "holding: client disconnected");
}

TEST(RunFaults, DuplicateMeasurementIsRefused) {
  const FaultRun r = RunAgainstBench("duplicate", {"--inject", "duplicate@61"});
  EXPECT_EQ(r.status, kTransferStatus) << r.output;
  ExpectContains(r.output, "stale or duplicate sequence number");
  ExpectCommittedRows(r, RowsForCommand(61));
  ExpectContains(r.bench_log, "holding: client disconnected");
}

TEST(RunFaults, SilentBenchTimesOut) {
  const FaultRun r = RunAgainstBench("silence", {"--inject", "silence@80"});
  EXPECT_EQ(r.status, kTransferStatus) << r.output;
  ExpectContains(r.output, "did not answer within 1 s");
  // timeout (1 s) + a few seconds for the 159 exchanges before it and the process overhead.
  EXPECT_LT(r.seconds, 1.0 + 5.0);
  RecordProperty("run_seconds", fmt::format("{:.3f}", r.seconds));
  ExpectCommittedRows(r, RowsForCommand(80));
  ExpectContains(r.bench_log, "holding: FAULT silence at command 80");
  ExpectContains(r.bench_log, "holding: client disconnected");
}

}  // namespace
}  // namespace hybridtest
