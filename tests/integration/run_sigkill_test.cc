// A hybrid test killed with SIGKILL mid-run (a crash, a power-off of the PC's process, an
// operator's kill -9) loses no committed step: the journal holds rows 0..k with consecutive
// times, every row parses, and the sidecar still says "running" (it was never finished).
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

TEST(RunSigkill, EveryCommittedRowSurvives) {
  const fs::path dir = fs::temp_directory_path() / fmt::format("hybridtest_sigkill_{}", ::getpid());
  fs::remove_all(dir);
  fs::create_directories(dir);
  const fs::path csv = dir / "killed.csv";
  Child run({HYBRIDTEST_BINARY, "run", std::string(HYBRIDTEST_SOURCE_DIR) + "/examples/rotor/emulated.yaml",
             "--out", csv.string(), "--quiet"},
            dir / "run.log");
  // Wait (bounded) until a few hundred steps are committed, then kill without warning.
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(60);
  while (CountLines(csv) < 300 && std::chrono::steady_clock::now() < deadline) {
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  ASSERT_GE(CountLines(csv), 300) << "the run did not get going: " << run.output();
  run.Signal(SIGKILL);
  ASSERT_EQ(run.WaitExit(10.0), 128 + SIGKILL);

  const io::RunData data = io::LoadRun(csv.string());
  ASSERT_GE(data.num_rows(), 299);
  const Eigen::VectorXd t = data.Get("t");
  for (long n = 0; n < data.num_rows(); ++n) {
    ASSERT_NEAR(t(n), 0.001 * static_cast<double>(n), 1e-12) << "row " << n;
  }
  for (const char* channel : {"q1", "u4", "r1", "r1_command", "r1_force", "r1_lab_time"}) {
    const Eigen::VectorXd v = data.Get(channel);
    for (long n = 0; n < data.num_rows(); ++n) ASSERT_TRUE(std::isfinite(v(n))) << channel << n;
  }
  EXPECT_EQ(data.metadata.value("status", ""), "running");
  // The stage record parses too (it may be a few rows behind or ahead of the journal).
  const io::RunData stages = io::LoadRun((dir / "killed.stages.csv").string());
  EXPECT_GE(stages.num_rows(), 2 * (data.num_rows() - 1));
  fs::remove_all(dir);
}

}  // namespace
}  // namespace hybridtest
