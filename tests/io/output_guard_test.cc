// OutputGuard: no command writes over a file it reads or onto a device or a FIFO
// (output_guard.h).
#include "hybridtest/io/output_guard.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <sys/stat.h>
#include <unistd.h>

#include <filesystem>

#include "hybridtest/common/error.h"
#include "support/temp_dir.h"

namespace hybridtest::io {
namespace {

namespace fs = std::filesystem;
using ::testing::AllOf;
using ::testing::HasSubstr;

std::string ErrorOf(const std::function<void()>& f) {
  try {
    f();
  } catch (const ConfigError& e) {
    return e.what();
  }
  return "(no error)";
}

// A finished run k.csv with its sidecar recording the config it read (../cfg/k.yaml).
fs::path MakeRun(const fs::path& dir) {
  fs::create_directories(dir / "results");
  fs::create_directories(dir / "cfg");
  test_support::WriteText(dir / "cfg" / "k.yaml", "duration: 1\n");
  test_support::WriteText(dir / "results" / "k.csv", "t,q1\n0,0\n");
  test_support::WriteText(
      dir / "results" / "k.meta.json",
      R"({"format": "hybridtest-journal/1", "status": "completed",
          "extra": {"inputs": [{"role": "config", "path": "../cfg/k.yaml"}]}})");
  return dir / "results" / "k.csv";
}

TEST(OutputGuard, RefusesEveryFileOfTheRunAndWhatItRead) {
  const fs::path dir = test_support::FreshTempDir("output_guard_files");
  const fs::path csv = MakeRun(dir);
  const auto inputs = RunProtectedFiles(csv.string());
  const std::string journal = test_support::ReadText(csv);
  EXPECT_THAT(ErrorOf([&] { CheckOutputFile(csv.string(), inputs, "--out"); }),
              AllOf(HasSubstr("--out " + csv.string()), HasSubstr("the journal of"),
                    HasSubstr("choose another --out")));
  EXPECT_THAT(ErrorOf([&] {
                CheckOutputFile((dir / "results" / "k.meta.json").string(), inputs, "--out");
              }),
              HasSubstr("the sidecar of"));
  EXPECT_THAT(ErrorOf([&] {
                CheckOutputFile((dir / "results" / "k.state.json").string(), inputs, "--csv");
              }),
              HasSubstr("the run state of"));
  // The recorded config, named another way (relative to the journal's directory).
  EXPECT_THAT(ErrorOf([&] {
                CheckOutputFile((dir / "cfg" / "." / "k.yaml").string(), inputs, "--hdf5");
              }),
              AllOf(HasSubstr("--hdf5"), HasSubstr("the config file of")));
  // A symlink to the journal and a hard link to it are the journal.
  fs::create_symlink(csv, dir / "link.csv");
  fs::create_hard_link(csv, dir / "hard.csv");
  EXPECT_THAT(ErrorOf([&] { CheckOutputFile((dir / "link.csv").string(), inputs, "--out"); }),
              HasSubstr("the journal of"));
  EXPECT_THAT(ErrorOf([&] { CheckOutputFile((dir / "hard.csv").string(), inputs, "--out"); }),
              HasSubstr("the journal of"));
  // Another file is allowed, existing or not.
  test_support::WriteText(dir / "old.html", "x");
  EXPECT_EQ(ErrorOf([&] { CheckOutputFile((dir / "old.html").string(), inputs, "--out"); }),
            "(no error)");
  EXPECT_EQ(ErrorOf([&] { CheckOutputFile((dir / "new.html").string(), inputs, "--out"); }),
            "(no error)");
  EXPECT_EQ(test_support::ReadText(csv), journal);
}

TEST(OutputGuard, RefusesDevicesAndFifosWithoutOpeningThem) {
  const fs::path dir = test_support::FreshTempDir("output_guard_fifo");
  const std::string fifo = (dir / "pipe").string();
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  // An open for writing would block on a FIFO without a reader: the check returns at once.
  EXPECT_THAT(ErrorOf([&] { CheckOutputFile(fifo, {}, "--out"); }),
              AllOf(HasSubstr("is a FIFO"), HasSubstr("regular files only")));
  EXPECT_THAT(ErrorOf([&] { CheckOutputFile("/dev/null", {}, "--out"); }),
              HasSubstr("is a device"));
  EXPECT_THAT(ErrorOf([&] { CheckOutputFile(dir.string(), {}, "--csv"); }),
              HasSubstr("is a directory"));
}

TEST(OutputGuard, ADirectoryOutputNeverReplacesAnInputInIt) {
  const fs::path dir = test_support::FreshTempDir("output_guard_dir");
  // A run named comparison.csv, compared into its own directory.
  test_support::WriteText(dir / "comparison.csv", "t,q1\n0,0\n");
  const auto inputs = RunProtectedFiles((dir / "comparison.csv").string(), "run A");
  EXPECT_THAT(ErrorOf([&] {
                CheckOutputDirectory(dir.string(), inputs, "--out", {"comparison.csv"}, {".png"});
              }),
              AllOf(HasSubstr("the journal of run A"), HasSubstr("choose another --out")));
  // A directory that only holds other files is fine, and so is a new one.
  EXPECT_EQ(ErrorOf([&] {
              CheckOutputDirectory(dir.string(), inputs, "--out", {}, {".png", ".svg"});
            }),
            "(no error)");
  EXPECT_EQ(ErrorOf([&] {
              CheckOutputDirectory((dir / "new").string(), inputs, "--out", {}, {".png"});
            }),
            "(no error)");
  // The journal given as the directory.
  EXPECT_THAT(ErrorOf([&] {
                CheckOutputDirectory((dir / "comparison.csv").string(), inputs, "--out", {}, {});
              }),
              AllOf(HasSubstr("is a file this command reads"), HasSubstr("not a directory")));
  EXPECT_EQ(test_support::ReadText(dir / "comparison.csv"), "t,q1\n0,0\n");
}

}  // namespace
}  // namespace hybridtest::io
