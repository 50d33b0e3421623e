// A journal on a full disk: a row is written whole or not at all, and the stop is recorded.
// The full disk is emulated with RLIMIT_FSIZE in a forked child (writes past the limit fail
// with EFBIG, SIGXFSZ ignored): deterministic, and no root needed. A real full file system
// (a small tmpfs) is used in tests/integration/results_kept_test.cc where the system allows it.
#include <fmt/format.h>
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <functional>
#include <sstream>

#include "hybridtest/common/error.h"
#include "hybridtest/io/csv.h"
#include "hybridtest/io/journal.h"
#include "support/temp_dir.h"

namespace hybridtest::io {
namespace {

namespace fs = std::filesystem;

using test_support::ReadText;

std::string TempDir(const std::string& name) {
  return test_support::FreshTempDir("full_disk_" + name).string();
}

// Runs `body` in a child process whose files cannot grow past `limit` bytes; returns its exit
// status (the body's return value, 99 if it threw).
int RunWithFileSizeLimit(rlim_t limit, const std::function<int()>& body, bool limit_first) {
  const pid_t child = ::fork();
  if (child == 0) {
    ::signal(SIGXFSZ, SIG_IGN);
    const rlimit rl{limit, limit};
    if (limit_first && ::setrlimit(RLIMIT_FSIZE, &rl) != 0) ::_exit(98);
    int code = 99;
    try {
      code = body();
    } catch (...) {
    }
    ::_exit(code);
  }
  int status = 0;
  ::waitpid(child, &status, 0);
  return WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
}

const std::vector<Channel> kChannels = {{"t", "s", ""}, {"q1", "m", ""}, {"u1", "m/s", ""}};

double Value(long n, int column) {
  return column == 0 ? 1e-3 * static_cast<double>(n) : std::sin(0.37 * static_cast<double>(n) + column);
}

// Every line of the CSV is whole: header, then rows of three numbers, ending with '\n'.
long ExpectWholeRows(const std::string& path) {
  const std::string text = ReadText(path);
  EXPECT_FALSE(text.empty());
  EXPECT_EQ(text.back(), '\n') << "the file ends with a partial row";
  std::istringstream in(text);
  std::string line;
  std::getline(in, line);
  EXPECT_EQ(line, "t,q1,u1");
  long rows = 0;
  while (std::getline(in, line)) {
    const auto fields = SplitCsvLine(line);
    EXPECT_EQ(fields.size(), 3u) << "row " << rows << ": " << line;
    for (std::size_t j = 0; j < fields.size(); ++j) {
      EXPECT_EQ(ParseCsvNumber(fields[j]), Value(rows, static_cast<int>(j))) << "row " << rows;
    }
    ++rows;
  }
  return rows;
}

TEST(JournalFullDisk, TheStopIsRecordedAndNoPartialRowIsLeft) {
  const std::string path = TempDir("rows") + "/run.csv";
  const rlim_t limit = 4000;  // [B]: about 60 rows, the sidecar fits
  const int code = RunWithFileSizeLimit(limit, [&] {
    Journal journal(path, kChannels, {}, SyncPolicy::kBatched, 7);
    std::vector<double> row(3);
    for (long n = 0; n < 100000; ++n) {
      for (int j = 0; j < 3; ++j) row[static_cast<std::size_t>(j)] = Value(n, j);
      try {
        journal.Append(row);
      } catch (const IoError& e) {
        // What the runner does on a failed write: record the stop.
        if (std::string(e.what()).find("File too large") == std::string::npos) return 3;
        journal.Finish({{"rows", journal.rows()}}, std::string("stopped: ") + e.what());
        return 0;
      }
    }
    return 4;  // the limit never bit
  }, /*limit_first=*/true);
  ASSERT_EQ(code, 0);
  const long rows = ExpectWholeRows(path);
  EXPECT_GT(rows, 10);
  EXPECT_LE(fs::file_size(path), limit);
  const nlohmann::json sidecar = nlohmann::json::parse(ReadText(SidecarPath(path)));
  const std::string status = sidecar["status"];
  EXPECT_EQ(status.rfind("stopped: ", 0), 0u) << status;
  EXPECT_NE(status.find(fmt::format("row {}", rows + 1)), std::string::npos) << status;
  EXPECT_EQ(sidecar["rows"], rows);
}

TEST(JournalFullDisk, ASidecarThatCannotBeWrittenIsReported) {
  const std::string path = TempDir("sidecar") + "/run.csv";
  JournalMetadata metadata;
  metadata.config_text = std::string(3000, '#');  // a sidecar of more than 3000 bytes
  const int code = RunWithFileSizeLimit(1000, [&] {
    Journal journal(path, kChannels, metadata, SyncPolicy::kEveryRow);
    std::vector<double> row(3);
    for (long n = 0; n < 5; ++n) {
      for (int j = 0; j < 3; ++j) row[static_cast<std::size_t>(j)] = Value(n, j);
      journal.Append(row);
    }
    // From now on no file may grow past 1000 bytes: the sidecar cannot be rewritten.
    const rlimit rl{1000, 1000};
    if (::setrlimit(RLIMIT_FSIZE, &rl) != 0) return 98;
    try {
      journal.Finish({}, "completed");
    } catch (const IoError& e) {
      const std::string message = e.what();
      return message.find("run.meta.json") != std::string::npos &&
                     message.find("File too large") != std::string::npos
                 ? 0
                 : 5;
    }
    return 6;  // Finish did not report the failure
  }, /*limit_first=*/false);
  ASSERT_EQ(code, 0);
  EXPECT_EQ(ExpectWholeRows(path), 5);
  // The previous sidecar is intact (the rewrite is atomic) and its temporary file is gone.
  const nlohmann::json sidecar = nlohmann::json::parse(ReadText(SidecarPath(path)));
  EXPECT_EQ(sidecar["status"], "running");
  EXPECT_FALSE(fs::exists(SidecarPath(path) + ".tmp"));
}

}  // namespace
}  // namespace hybridtest::io
