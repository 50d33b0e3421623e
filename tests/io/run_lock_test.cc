// RunLock: one master per run (run_lock.h).
#include "hybridtest/io/run_lock.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <optional>

#include "hybridtest/common/error.h"
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

}  // namespace
}  // namespace hybridtest::io
