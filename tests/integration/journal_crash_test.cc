// Crash safety of the Journal: a child process appends rows forever and reports each row
// whose Append() returned through a pipe; the parent SIGKILLs it mid-run. Every reported row
// must be in the file and parse; at most one more (appended but not yet reported) may follow.
#include <fmt/format.h>
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <vector>

#include "hybridtest/io/journal.h"
#include "hybridtest/io/run_reader.h"

namespace hybridtest::io {
namespace {

namespace fs = std::filesystem;

constexpr int kChannels = 16;

// The value a row holds in a column: checkable after the crash.
double Value(long row, int column) {
  return column == 0 ? 1e-3 * static_cast<double>(row)
                     : std::sin(0.1 * static_cast<double>(row) + column) * 1e3;
}

// The child: never returns.
[[noreturn]] void AppendForever(const std::string& path, SyncPolicy policy, int report_fd) {
  try {
    std::vector<Channel> channels{{"t", "s", "time"}};
    for (int j = 1; j < kChannels; ++j) channels.push_back({fmt::format("q{}", j), "m", ""});
    Journal journal(path, channels, JournalMetadata{}, policy, 50);
    std::vector<double> row(kChannels);
    for (long i = 0;; ++i) {
      for (int j = 0; j < kChannels; ++j) row[static_cast<std::size_t>(j)] = Value(i, j);
      journal.Append(row);
      if (::write(report_fd, &i, sizeof i) != sizeof i) ::_exit(3);
      ::usleep(100);
    }
  } catch (...) {
    ::_exit(2);
  }
}

struct CrashOutcome {
  long reported = 0;  // rows whose Append() returned, as the child said before dying
  RunData run;
};

CrashOutcome KillMidRun(SyncPolicy policy, long kill_after, const std::string& name) {
  const fs::path dir = fs::temp_directory_path() /
                       ("hybridtest_crash_" + name + "_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  fs::create_directories(dir);
  const std::string path = (dir / "run.csv").string();

  int fds[2];
  EXPECT_EQ(::pipe(fds), 0);
  const pid_t child = ::fork();
  if (child == 0) {
    ::close(fds[0]);
    AppendForever(path, policy, fds[1]);
  }
  ::close(fds[1]);
  CrashOutcome outcome;
  long index = 0;
  while (outcome.reported < kill_after && ::read(fds[0], &index, sizeof index) == sizeof index) {
    ++outcome.reported;
  }
  ::kill(child, SIGKILL);
  int status = 0;
  ::waitpid(child, &status, 0);
  EXPECT_TRUE(WIFSIGNALED(status) && WTERMSIG(status) == SIGKILL)
      << "the child died on its own, status " << status;
  // Reports written before the kill are still in the pipe.
  while (::read(fds[0], &index, sizeof index) == sizeof index) ++outcome.reported;
  ::close(fds[0]);
  outcome.run = LoadRun(path);
  return outcome;
}

void ExpectNoCommittedRowLost(const CrashOutcome& outcome) {
  const RunData& run = outcome.run;
  ASSERT_GE(outcome.reported, 1);
  EXPECT_GE(run.num_rows(), outcome.reported) << "committed rows were lost";
  EXPECT_LE(run.num_rows(), outcome.reported + 1);
  ASSERT_EQ(run.num_channels(), kChannels);
  for (long i = 0; i < run.num_rows(); ++i) {
    for (int j = 0; j < kChannels; ++j) {
      ASSERT_EQ(run.values(i, j), Value(i, j)) << "row " << i << " column " << j;
    }
  }
  // The run never finished: its sidecar still says so.
  EXPECT_EQ(run.metadata.at("status"), "running");
  for (const auto& warning : run.warnings) {
    EXPECT_NE(warning.find("truncated last line"), std::string::npos) << warning;
  }
}

TEST(JournalCrash, BatchedLosesNoRowOnSigkill) {
  for (const long kill_after : {1L, 137L, 600L}) {
    SCOPED_TRACE(kill_after);
    ExpectNoCommittedRowLost(KillMidRun(SyncPolicy::kBatched, kill_after, "batched"));
  }
}

TEST(JournalCrash, EveryRowLosesNoRowOnSigkill) {
  for (const long kill_after : {1L, 60L, 200L}) {
    SCOPED_TRACE(kill_after);
    ExpectNoCommittedRowLost(KillMidRun(SyncPolicy::kEveryRow, kill_after, "every_row"));
  }
}

}  // namespace
}  // namespace hybridtest::io
