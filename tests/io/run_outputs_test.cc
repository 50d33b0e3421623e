// The checks that keep results and inputs from being written over (run_outputs.h).
#include "hybridtest/io/run_outputs.h"

#include <gtest/gtest.h>
#include <sys/stat.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>

#include "hybridtest/common/error.h"
#include "support/temp_dir.h"

namespace hybridtest::io {
namespace {

namespace fs = std::filesystem;

fs::path TempDir(const std::string& name) {
  return test_support::FreshTempDir("outputs_" + name);
}

std::string MessageOf(const std::string& csv, const std::vector<std::string>& inputs,
                      bool overwrite) {
  try {
    CheckRunOutputs(csv, inputs, overwrite);
  } catch (const ConfigError& e) {
    return e.what();
  }
  return "";
}

TEST(RunOutputs, TheFourFilesOfARun) {
  EXPECT_EQ(RunOutputFiles("results/k.csv"),
            (std::vector<std::string>{"results/k.csv", "results/k.meta.json",
                                      "results/k.stages.csv", "results/k.stages.meta.json"}));
}

TEST(RunOutputs, AnyExistingFileOfTheRunNeedsOverwrite) {
  const fs::path dir = TempDir("exists");
  const std::string csv = (dir / "k.csv").string();
  EXPECT_EQ(MessageOf(csv, {}, false), "");
  for (const char* name : {"k.stages.meta.json", "k.stages.csv", "k.meta.json", "k.csv"}) {
    std::ofstream(dir / name) << "x";
    const std::string message = MessageOf(csv, {}, false);
    EXPECT_NE(message.find((dir / name).string() + ": exists already"), std::string::npos)
        << message;
    EXPECT_NE(message.find("pass --overwrite"), std::string::npos) << message;
    EXPECT_EQ(MessageOf(csv, {}, true), "");
  }
  // A dangling symlink is something at that name too.
  fs::create_symlink(dir / "nowhere", dir / "d.csv");
  EXPECT_NE(MessageOf((dir / "d.csv").string(), {}, false), "");
}

TEST(RunOutputs, AnInputIsRefusedEvenWithOverwrite) {
  const fs::path dir = TempDir("inputs");
  const std::string config = (dir / "c.yaml").string();
  std::ofstream(config) << "model: {name: rotor}\n";
  fs::create_directories(dir / "sub");
  fs::create_symlink(config, dir / "alias.csv");
  for (const std::string& out : {config, (dir / "sub" / ".." / "c.yaml").string(),
                                 (dir / "." / "c.yaml").string(), (dir / "alias.csv").string()}) {
    const std::string message = MessageOf(out, {config}, true);
    EXPECT_NE(message.find("a file it reads"), std::string::npos) << out << ": " << message;
  }
  // The sidecar of k.csv is k.meta.json: an input of that name is protected too.
  const std::string message = MessageOf((dir / "c.csv").string(), {(dir / "c.meta.json").string()}, true);
  EXPECT_NE(message.find("c.meta.json"), std::string::npos) << message;
  // Relative and absolute spellings of one file.
  const fs::path cwd = fs::current_path();
  fs::current_path(dir);
  EXPECT_TRUE(SameFile("c.yaml", config));
  EXPECT_TRUE(SameFile("./sub/../c.yaml", config));
  EXPECT_FALSE(SameFile("other.yaml", config));
  fs::current_path(cwd);
}

TEST(RunOutputs, DevicesFifosDirectoriesAndSymlinksAreNeverReplaced) {
  const fs::path dir = TempDir("kinds");
  const std::string message = MessageOf("/dev/null", {}, true);
  EXPECT_NE(message.find("/dev/null: is a device"), std::string::npos) << message;
  ASSERT_EQ(::mkfifo((dir / "f.csv").c_str(), 0600), 0);
  EXPECT_NE(MessageOf((dir / "f.csv").string(), {}, true).find("is a FIFO"), std::string::npos);
  fs::create_directories(dir / "d.meta.json");
  EXPECT_NE(MessageOf((dir / "d.csv").string(), {}, true).find("is a directory"),
            std::string::npos);
  std::ofstream(dir / "target.txt") << "x";
  fs::create_symlink(dir / "target.txt", dir / "s.csv");
  EXPECT_NE(MessageOf((dir / "s.csv").string(), {}, true).find("is a symbolic link"),
            std::string::npos);
  // The run state is an output too.
  std::ofstream(dir / "k.state.json") << "{}";
  EXPECT_NE(MessageOf((dir / "k.csv").string(), {}, false).find("k.state.json: exists already"),
            std::string::npos);
}

TEST(RunOutputs, TheRunsLockFileIsNeverAnInput) {
  const fs::path dir = TempDir("lock_input");
  // An empty file (the lock itself would not refuse it) named like the run's lock.
  std::ofstream(dir / "k.lock").close();
  const std::string message =
      MessageOf((dir / "k.csv").string(), {(dir / "k.lock").string()}, true);
  EXPECT_NE(message.find("k.lock would be written over"), std::string::npos) << message;
}

}  // namespace
}  // namespace hybridtest::io
