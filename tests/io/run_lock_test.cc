// RunLock: one master per run (run_lock.h).
#include "hybridtest/io/run_lock.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <memory>
#include <optional>

#include "hybridtest/common/error.h"
#include "hybridtest/io/journal.h"
#include "support/temp_dir.h"

namespace hybridtest::io {
namespace {

using ::testing::AllOf;
using ::testing::HasSubstr;

TEST(RunLock, ASecondHolderIsRefusedWithTheFirstsPidAndHost) {
  const auto dir = test_support::FreshTempDir("run_lock");
  const std::string csv = (dir / "k.csv").string();
  EXPECT_EQ(RunLockPath(csv), (dir / "k.lock").string());
  std::optional<RunLock> first(RunLock::Acquire(csv, "run"));
  // flock belongs to an open file description: a second one in the same process conflicts
  // exactly as another process would.
  std::string message;
  try {
    RunLock::Acquire(csv, "resume");
  } catch (const ConfigError& e) {
    message = e.what();
  }
  char host[256] = {};
  ::gethostname(host, sizeof host - 1);
  EXPECT_THAT(message, AllOf(HasSubstr("in use by another hybridtest process"),
                             HasSubstr("pid " + std::to_string(::getpid())),
                             HasSubstr(std::string("host ") + host), HasSubstr("hybridtest run"),
                             HasSubstr("hybridtest resume " + csv)));
  // Released with its holder, which removes the file.
  first.reset();
  EXPECT_FALSE(std::filesystem::exists(dir / "k.lock"));
  EXPECT_NO_THROW(RunLock::Acquire(csv, "resume"));
}

TEST(RunLock, AStaleLockFileLeftByAKilledHolderDoesNotBlock) {
  const auto dir = test_support::FreshTempDir("run_lock_stale");
  test_support::WriteText(dir / "k.lock", "pid 1 on host gone, hybridtest run, since then\n");
  const RunLock lock = RunLock::Acquire((dir / "k.csv").string(), "resume");
  EXPECT_THAT(test_support::ReadText(dir / "k.lock"),
              HasSubstr("pid " + std::to_string(::getpid())));
}

TEST(RunLock, ASymlinkAtTheLocksNameIsNeverFollowed) {
  const auto dir = test_support::FreshTempDir("run_lock_symlink");
  test_support::WriteText(dir / "precious.txt", "keep me\n");
  std::filesystem::create_symlink(dir / "precious.txt", dir / "k.lock");
  EXPECT_THROW(RunLock::Acquire((dir / "k.csv").string(), "run"), IoError);
  EXPECT_EQ(test_support::ReadText(dir / "precious.txt"), "keep me\n");
}

TEST(RunLock, AFileThatIsNotALockFileIsNeverTruncatedOrRemoved) {
  const auto dir = test_support::FreshTempDir("run_lock_config");
  // A config named like the run's lock file.
  test_support::WriteText(dir / "k.lock", "duration: 1.0\n");
  std::string message;
  try {
    RunLock::Acquire((dir / "k.csv").string(), "run");
  } catch (const ConfigError& e) {
    message = e.what();
  }
  EXPECT_THAT(message, AllOf(HasSubstr("not a hybridtest lock file"), HasSubstr("untouched"),
                             HasSubstr("choose another --out")));
  EXPECT_EQ(test_support::ReadText(dir / "k.lock"), "duration: 1.0\n");
}

TEST(RunLock, AnEmptyFileFoundAtTheLocksNameIsNotRemoved) {
  const auto dir = test_support::FreshTempDir("run_lock_empty");
  test_support::WriteText(dir / "k.lock", "");
  { const RunLock lock = RunLock::Acquire((dir / "k.csv").string(), "run"); }
  EXPECT_TRUE(std::filesystem::exists(dir / "k.lock"));
  // A lock file it created is removed.
  { const RunLock lock = RunLock::Acquire((dir / "m.csv").string(), "run"); }
  EXPECT_FALSE(std::filesystem::exists(dir / "m.lock"));
}

// A live writer: a journal published with one row and kept open.
std::unique_ptr<Journal> LiveJournal(const std::string& csv) {
  auto journal = std::make_unique<Journal>(csv, std::vector<Channel>{{"t", "s", "time"}},
                                           JournalMetadata{}, SyncPolicy::kEveryRow);
  const std::vector<double> row{0.0};
  journal->Append(row);
  return journal;
}

TEST(RunLock, RemovingTheLockFileOfALiveRunDoesNotLetASecondProcessIn) {
  const auto dir = test_support::FreshTempDir("run_lock_removed");
  const std::string csv = (dir / "k.csv").string();
  std::optional<RunLock> first(RunLock::Acquire(csv, "run"));
  const auto journal = LiveJournal(csv);
  const std::string before = test_support::ReadText(csv);
  std::filesystem::remove(RunLockPath(csv));
  // The journal's own lock refuses: a resume, a run --overwrite, a reopen, a cut.
  std::string message;
  try {
    RunLock::Acquire(csv, "resume");
  } catch (const ConfigError& e) {
    message = e.what();
  }
  EXPECT_THAT(message, AllOf(HasSubstr("a live hybridtest process"),
                             HasSubstr("pid " + std::to_string(::getpid())),
                             HasSubstr("removed or replaced"), HasSubstr("nothing was changed")));
  EXPECT_FALSE(std::filesystem::exists(RunLockPath(csv)));  // the refused one removed its own
  EXPECT_THROW(Journal(kReopenForAppend, csv, SyncPolicy::kEveryRow), ConfigError);
  EXPECT_EQ(test_support::ReadText(csv), before);
}

TEST(RunLock, AResumeHoldsTheJournalAndItsOwnWriterMayReopenIt) {
  const auto dir = test_support::FreshTempDir("run_lock_resume");
  const std::string csv = (dir / "k.csv").string();
  {
    const auto journal = LiveJournal(csv);
    journal->Finish({}, "stopped: test");
  }
  std::optional<RunLock> resume(RunLock::Acquire(csv, "resume"));
  // This process holds the journal through its RunLock: its own reopening is allowed...
  std::optional<Journal> reopened(std::in_place, kReopenForAppend, csv, SyncPolicy::kEveryRow);
  EXPECT_EQ(reopened->rows(), 1);
  // ...and while it holds it, a second RunLock (another process, after the lock file was
  // removed) is refused on the journal.
  std::filesystem::remove(RunLockPath(csv));
  EXPECT_THROW(RunLock::Acquire(csv, "resume"), ConfigError);
  reopened.reset();
  resume.reset();
  EXPECT_NO_THROW(RunLock::Acquire(csv, "resume"));
}

}  // namespace
}  // namespace hybridtest::io
