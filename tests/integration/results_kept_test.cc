// Results are never destroyed (docs/results-format.md, "Never destroyed"): `run` and
// `simulate` refuse to write over an earlier run without --overwrite (exit 2, the files stay
// byte-identical), never write over a file they read, and a run stopped by a full disk
// records its status and ends its CSV with a whole row. Real processes.
#include <fmt/format.h>
#include <fmt/ranges.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdlib>
#include <map>

#include "hybridtest/io/journal.h"
#include "hybridtest/io/run_reader.h"
#include "integration/child_process.h"

namespace hybridtest {
namespace {

namespace fs = std::filesystem;

const std::string kExamples = std::string(HYBRIDTEST_SOURCE_DIR) + "/examples/rotor/";

fs::path FreshDir(const std::string& name) {
  const fs::path dir = fs::temp_directory_path() / fmt::format("hybridtest_kept_{}_{}", name, ::getpid());
  fs::remove_all(dir);
  fs::create_directories(dir);
  return dir;
}

struct Outcome {
  int status;
  std::string output;
};

// hybridtest ARGS..., with a bounded wait.
Outcome Hybridtest(const fs::path& dir, std::vector<std::string> args) {
  args.insert(args.begin(), HYBRIDTEST_BINARY);
  Child child(args, dir / "command.log");
  const int status = child.WaitExit(120.0);
  return {status, child.output()};
}

std::vector<std::string> FilesIn(const fs::path& dir) {
  std::vector<std::string> names;
  for (const auto& entry : fs::directory_iterator(dir)) {
    if (entry.path().filename() != "command.log") names.push_back(entry.path().filename());
  }
  std::sort(names.begin(), names.end());
  return names;
}

TEST(ResultsKept, AnEarlierRunIsNotReplacedWithoutOverwrite) {
  const fs::path dir = FreshDir("refuse");
  const std::string csv = (dir / "k.csv").string();
  ASSERT_EQ(Hybridtest(dir, {"simulate", kExamples + "numerical.yaml", "--out", csv, "--quiet"}).status, 0);
  const std::string csv_bytes = ReadText(csv);
  const std::string sidecar_bytes = ReadText(io::SidecarPath(csv));

  // The example: a hybrid test that could not even start destroyed the result.
  for (const auto& args : std::vector<std::vector<std::string>>{
           {"run", kExamples + "remote.yaml", "--bench", "127.0.0.1:9", "--out", csv},
           {"simulate", kExamples + "numerical.yaml", "--out", csv}}) {
    const Outcome o = Hybridtest(dir, args);
    EXPECT_EQ(o.status, 2) << o.output;
    EXPECT_NE(o.output.find(csv + ": exists already"), std::string::npos) << o.output;
    EXPECT_NE(o.output.find("--overwrite"), std::string::npos) << o.output;
    EXPECT_NE(o.output.find("another --out"), std::string::npos) << o.output;
  }
  EXPECT_EQ(ReadText(csv), csv_bytes);
  EXPECT_EQ(ReadText(io::SidecarPath(csv)), sidecar_bytes);
  EXPECT_EQ(FilesIn(dir), (std::vector<std::string>{"k.csv", "k.meta.json", "k.state.json"}));

  // A stage record alone is a run too.
  std::ofstream(dir / "s.stages.csv") << "step\n";
  const Outcome o = Hybridtest(dir, {"simulate", kExamples + "numerical.yaml", "--out",
                                     (dir / "s.csv").string()});
  EXPECT_EQ(o.status, 2);
  EXPECT_NE(o.output.find("s.stages.csv: exists already"), std::string::npos) << o.output;

  // --overwrite replaces the run.
  const Outcome again = Hybridtest(dir, {"simulate", kExamples + "numerical.yaml", "--out", csv,
                                         "--quiet", "--overwrite"});
  ASSERT_EQ(again.status, 0) << again.output;
  EXPECT_EQ(io::ReadSidecar(csv)["status"], "completed");
  EXPECT_EQ(ReadText(csv), csv_bytes);  // the same deterministic simulation
  fs::remove_all(dir);
}

TEST(ResultsKept, AnInputIsNeverAnOutput) {
  const fs::path dir = FreshDir("inputs");
  fs::copy_file(kExamples + "numerical.yaml", dir / "c.yaml");
  fs::copy_file(kExamples + "emulated.yaml", dir / "emulated.yaml");
  fs::copy_file(kExamples + "bench-cantilever.yaml", dir / "bench-cantilever.yaml");
  fs::copy_file(kExamples + "numerical.yaml", dir / "m.meta.json");  // a config named oddly
  fs::create_symlink(dir / "c.yaml", dir / "link.csv");
  const std::string c = (dir / "c.yaml").string();
  const std::vector<std::vector<std::string>> attempts = {
      {"simulate", c, "--out", c},
      {"simulate", c, "--out", (dir / "." / "c.yaml").string()},
      {"simulate", c, "--out", (dir / "link.csv").string()},
      {"simulate", (dir / "m.meta.json").string(), "--out", (dir / "m.csv").string()},
      {"run", (dir / "emulated.yaml").string(), "--out", (dir / "bench-cantilever.yaml").string()},
  };
  std::map<std::string, std::string> before;
  for (const auto& name : FilesIn(dir)) before[name] = ReadText(dir / name);
  for (const auto& args : attempts) {
    std::vector<std::string> with_flag = args;
    with_flag.push_back("--overwrite");  // not even with --overwrite
    const Outcome o = Hybridtest(dir, with_flag);
    EXPECT_EQ(o.status, 2) << fmt::format("{}", fmt::join(args, " ")) << "\n" << o.output;
    EXPECT_NE(o.output.find("a file it reads"), std::string::npos) << o.output;
  }
  for (const auto& [name, text] : before) EXPECT_EQ(ReadText(dir / name), text) << name;
  EXPECT_EQ(FilesIn(dir).size(), before.size());
  fs::remove_all(dir);
}

// A run into a tmpfs that another writer fills while the run goes on (the run's own pre-run
// check refuses to start when its output cannot fit, so the disk must fill under it). Needs a
// private mount namespace (unshare -rm, or root); skipped where the system does not allow one.
TEST(ResultsKept, AFullDiskStopIsRecordedWithWholeRows) {
  if (std::system("unshare -rm true >/dev/null 2>&1") != 0) {
    GTEST_SKIP() << "no private mount namespace here (unshare -rm); the full disk is emulated "
                    "with RLIMIT_FSIZE in tests/io/journal_full_disk_test.cc";
  }
  const fs::path dir = FreshDir("full");
  fs::create_directories(dir / "disk");
  fs::create_directories(dir / "copy");
  const std::string script = fmt::format(
      "mount -t tmpfs -o size=80m tmpfs '{0}/disk' || exit 90; "
      "'{1}' run '{2}emulated.yaml' --out '{0}/disk/k.csv' --quiet > '{0}/copy/log' 2>&1 & "
      "pid=$!; n=0; "
      "while [ \"$(cat '{0}/disk/k.csv' 2>/dev/null | wc -l)\" -lt 300 ] && [ $n -lt 600 ]; do "
      "sleep 0.05; n=$((n+1)); done; "
      "dd if=/dev/zero of='{0}/disk/filler' bs=64k 2>/dev/null; "
      "wait $pid; echo $? > '{0}/copy/status'; rm -f '{0}/disk/filler'; "
      "cp -a '{0}/disk/.' '{0}/copy/'",
      dir.string(), HYBRIDTEST_BINARY, kExamples);
  Child child({"/usr/bin/unshare", "-rm", "/bin/sh", "-c", script}, dir / "command.log");
  ASSERT_EQ(child.WaitExit(120.0), 0) << child.output();
  const fs::path copy = dir / "copy";
  const std::string log = ReadText(copy / "log");
  EXPECT_EQ(ReadText(copy / "status"), "1\n") << log;
  EXPECT_NE(log.find("No space left on device"), std::string::npos) << log;

  const std::string csv = (copy / "k.csv").string();
  const std::string text = ReadText(csv);
  ASSERT_FALSE(text.empty());
  EXPECT_EQ(text.back(), '\n') << "a partial row was left";
  const io::RunData data = io::LoadRun(csv);
  EXPECT_TRUE(data.warnings.empty()) << data.warnings.front();
  EXPECT_GT(data.num_rows(), 100);
  EXPECT_LT(data.num_rows(), 10001);
  const std::string status = data.metadata.value("status", "");
  EXPECT_EQ(status.rfind("stopped: ", 0), 0u) << status;
  EXPECT_NE(status.find("No space left on device"), std::string::npos) << status;
  EXPECT_EQ(data.metadata["rows"], data.num_rows());
  fs::remove_all(dir);
}

// A run that commits nothing (Activate() fails) writes no row, so its journal is never
// published.
TEST(ResultsKept, ARunThatCannotStartLeavesNoFile) {
  const fs::path dir = FreshDir("no_start");
  const Outcome o = Hybridtest(dir, {"run", kExamples + "remote.yaml", "--bench", "127.0.0.1:9",
                                     "--out", (dir / "k.csv").string(), "--quiet"});
  EXPECT_EQ(o.status, 4) << o.output;
  EXPECT_TRUE(FilesIn(dir).empty()) << FilesIn(dir).front();
  fs::remove_all(dir);
}

TEST(ResultsKept, ARunThatCannotStartKeepsTheRunItWouldReplace) {
  const fs::path dir = FreshDir("no_start_overwrite");
  const std::string csv = (dir / "k.csv").string();
  ASSERT_EQ(Hybridtest(dir, {"simulate", kExamples + "numerical.yaml", "--out", csv, "--quiet"}).status, 0);
  const std::string csv_bytes = ReadText(csv);
  const std::string sidecar_bytes = ReadText(io::SidecarPath(csv));
  const Outcome o = Hybridtest(dir, {"run", kExamples + "remote.yaml", "--bench", "127.0.0.1:9",
                                     "--out", csv, "--quiet", "--overwrite"});
  EXPECT_EQ(o.status, 4) << o.output;
  EXPECT_EQ(ReadText(csv), csv_bytes);
  EXPECT_EQ(ReadText(io::SidecarPath(csv)), sidecar_bytes);
  EXPECT_EQ(FilesIn(dir), (std::vector<std::string>{"k.csv", "k.meta.json", "k.state.json"}));
  fs::remove_all(dir);
}

}  // namespace
}  // namespace hybridtest
