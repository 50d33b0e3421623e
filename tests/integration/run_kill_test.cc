// A hybrid test ended from outside mid-run loses no committed step. SIGKILL (a crash, kill -9):
// the journal holds rows 0..k with consecutive times, every row parses, and the sidecar still
// says "running". SIGINT or SIGTERM (Ctrl-C, a service stop): the run stops after the current
// step, exits with 130, and the sidecar says "stopped: interrupted ...".
#include <fmt/format.h>
#include <gtest/gtest.h>

#include <cmath>

#include "hybridtest/io/run_reader.h"
#include "integration/child_process.h"

namespace hybridtest {
namespace {

namespace fs = std::filesystem;

long CountLines(const fs::path& path) {
  std::ifstream in(path);
  long lines = 0;
  std::string line;
  while (std::getline(in, line)) ++lines;
  return lines;
}

fs::path FreshDir(const std::string& name) {
  const fs::path dir = fs::temp_directory_path() / fmt::format("hybridtest_{}_{}", name, ::getpid());
  fs::remove_all(dir);
  fs::create_directories(dir);
  return dir;
}

// Starts the paper's emulated hybrid test and waits (bounded) until `rows` lines are on disk.
std::unique_ptr<Child> StartEmulatedRun(const fs::path& csv, long rows) {
  auto run = std::make_unique<Child>(
      std::vector<std::string>{HYBRIDTEST_BINARY, "run",
                               std::string(HYBRIDTEST_SOURCE_DIR) + "/examples/rotor/emulated.yaml",
                               "--out", csv.string(), "--quiet"},
      csv.parent_path() / "run.log");
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(60);
  while (CountLines(csv) < rows && std::chrono::steady_clock::now() < deadline) {
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  return run;
}

// Rows 0..k with t = n·h, all finite in the given channels.
void ExpectConsecutiveRows(const io::RunData& data, std::initializer_list<const char*> channels) {
  const Eigen::VectorXd t = data.Get("t");
  for (long n = 0; n < data.num_rows(); ++n) {
    ASSERT_NEAR(t(n), 0.001 * static_cast<double>(n), 1e-12) << "row " << n;
  }
  for (const char* channel : channels) {
    const Eigen::VectorXd v = data.Get(channel);
    for (long n = 0; n < data.num_rows(); ++n) ASSERT_TRUE(std::isfinite(v(n))) << channel << n;
  }
}

TEST(RunInterrupt, CtrlCStopsAfterTheStepAndWritesEverything) {
  const fs::path dir = FreshDir("sigint");
  const fs::path csv = dir / "interrupted.csv";
  auto run = StartEmulatedRun(csv, 300);
  ASSERT_GE(CountLines(csv), 300) << "the run did not get going: " << run->output();
  run->Signal(SIGINT);
  ASSERT_EQ(run->WaitExit(10.0), 130) << run->output();
  EXPECT_NE(run->output().find("interrupted by the operator"), std::string::npos) << run->output();

  const io::RunData data = io::LoadRun(csv.string());
  EXPECT_TRUE(data.warnings.empty());  // a clean stop: no cut-off last line
  // Every row seen before the signal (300 lines: the header and 299 rows) is there; the signal
  // may land while the last of them is being synced, and then no further step is taken.
  ASSERT_GE(data.num_rows(), 299);
  // The last row is the last committed state, with the forces measured there (the scheme's
  // trial of x_{n+1} belongs to the step; decision 0007): a resume starts from it.
  const long k = data.num_rows() - 1;
  EXPECT_TRUE(std::isfinite(data.Get("r1")(k)));
  ExpectConsecutiveRows(data, {"q1", "u4"});
  const std::string status = data.metadata.value("status", "");
  EXPECT_EQ(status.rfind("stopped: interrupted by the operator", 0), 0u) << status;
  EXPECT_EQ(data.metadata["statistics"]["stop"]["kind"], "interrupted");
  fs::remove_all(dir);
}

TEST(RunSigkill, EveryCommittedRowSurvives) {
  const fs::path dir = FreshDir("sigkill");
  const fs::path csv = dir / "killed.csv";
  auto run = StartEmulatedRun(csv, 300);
  ASSERT_GE(CountLines(csv), 300) << "the run did not get going: " << run->output();
  run->Signal(SIGKILL);  // without warning
  ASSERT_EQ(run->WaitExit(10.0), 128 + SIGKILL);

  const io::RunData data = io::LoadRun(csv.string());
  ASSERT_GE(data.num_rows(), 299);
  ExpectConsecutiveRows(data, {"q1", "u4", "r1", "r1_command", "r1_force", "r1_lab_time"});
  EXPECT_EQ(data.metadata.value("status", ""), "running");
  // The stage record parses too (it may be a few rows behind or ahead of the journal).
  const io::RunData stages = io::LoadRun((dir / "killed.stages.csv").string());
  EXPECT_GE(stages.num_rows(), 2 * (data.num_rows() - 1));
  fs::remove_all(dir);
}

}  // namespace
}  // namespace hybridtest
