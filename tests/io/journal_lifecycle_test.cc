// The life of a journal file (journal.h): staged until its first row, published by it, never
// replacing an older run before that; reopened for appending after its last complete row
// (resume), a partial last line cut. Row format and sidecar content: journal_test.cc.
#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "hybridtest/common/error.h"
#include "hybridtest/io/journal.h"
#include "support/temp_dir.h"

namespace hybridtest::io {
namespace {

namespace fs = std::filesystem;

using test_support::ReadText;
using test_support::WriteText;

std::string TempDir(const std::string& name) {
  return test_support::FreshTempDir("lifecycle_" + name).string();
}

nlohmann::json ReadJson(const std::string& path) { return nlohmann::json::parse(ReadText(path)); }

const std::vector<Channel> kChannels = {{"t", "s", "time"}, {"q1", "m", "deflection"}};

std::vector<std::string> FilesIn(const std::string& dir) {
  std::vector<std::string> names;
  for (const auto& entry : fs::directory_iterator(dir)) names.push_back(entry.path().filename());
  std::sort(names.begin(), names.end());
  return names;
}

TEST(JournalLifecycle, NothingAtTheFinalPathsUntilTheFirstRow) {
  const std::string dir = TempDir("staged");
  const std::string path = dir + "/run.csv";
  Journal journal(path, kChannels, {}, SyncPolicy::kBatched);
  EXPECT_FALSE(journal.published());
  EXPECT_FALSE(fs::exists(path));
  EXPECT_FALSE(fs::exists(SidecarPath(path)));
  EXPECT_EQ(ReadText(StagedPath(path)), "t,q1\n");
  EXPECT_EQ(ReadJson(StagedPath(SidecarPath(path)))["status"], "running");

  const double row[] = {0.0, 0.25};
  journal.Append(row);
  EXPECT_TRUE(journal.published());
  EXPECT_EQ(ReadText(path), "t,q1\n0,0.25\n");
  EXPECT_EQ(ReadJson(SidecarPath(path))["status"], "running");
  EXPECT_FALSE(fs::exists(StagedPath(path)));
  EXPECT_FALSE(fs::exists(StagedPath(SidecarPath(path))));
  journal.Finish({}, "completed");
  EXPECT_EQ(FilesIn(dir), (std::vector<std::string>{"run.csv", "run.meta.json"}));
}

TEST(JournalLifecycle, AnOlderRunSurvivesANewOneWithoutRows) {
  const std::string dir = TempDir("older");
  const std::string path = dir + "/run.csv";
  const std::string old_csv = "t,q1\n0,1\n0.001,2\n";
  const std::string old_sidecar = "{\"status\": \"completed\"}\n";
  WriteText(path, old_csv);
  WriteText(SidecarPath(path), old_sidecar);
  {
    // Finished before any row: a run that could not start.
    Journal journal(path, kChannels, {}, SyncPolicy::kEveryRow);
    journal.Finish({{"steps", 0}}, "stopped: connection refused");
  }
  {
    // Unwound before any row.
    Journal journal(path, kChannels, {}, SyncPolicy::kEveryRow);
  }
  EXPECT_EQ(ReadText(path), old_csv);
  EXPECT_EQ(ReadText(SidecarPath(path)), old_sidecar);
  EXPECT_EQ(FilesIn(dir), (std::vector<std::string>{"run.csv", "run.meta.json"}));

  // The first row of a new run replaces both files.
  Journal journal(path, kChannels, {}, SyncPolicy::kEveryRow);
  const double row[] = {0.0, 3.0};
  journal.Append(row);
  EXPECT_EQ(ReadText(path), "t,q1\n0,3\n");
  EXPECT_EQ(ReadJson(SidecarPath(path))["status"], "running");
}

TEST(JournalLifecycle, AFreshRunWithoutRowsLeavesNoFile) {
  const std::string dir = TempDir("fresh");
  {
    Journal journal(dir + "/run.csv", kChannels, {}, SyncPolicy::kBatched);
    journal.Finish({}, "stopped: bad bench address");
  }
  EXPECT_TRUE(FilesIn(dir).empty()) << FilesIn(dir).front();
}

// A journal of `rows` rows (t = 0.001 n, q1 = n / 3), stopped.
std::string WriteStoppedJournal(const std::string& path, long rows) {
  Journal journal(path, kChannels, {}, SyncPolicy::kBatched, 2);
  for (long n = 0; n < rows; ++n) {
    const double row[] = {1e-3 * static_cast<double>(n), static_cast<double>(n) / 3.0};
    journal.Append(row);
  }
  journal.Finish({{"steps", rows}}, "stopped: interrupted by the operator");
  return ReadText(path);
}

TEST(JournalLifecycle, ReopenAppendsAfterTheLastRowAndCutsAPartialLine) {
  const std::string dir = TempDir("reopen");
  const std::string whole = dir + "/whole.csv";
  const std::string path = dir + "/run.csv";
  const std::string uninterrupted = WriteStoppedJournal(whole, 5);
  const std::string before = WriteStoppedJournal(path, 3);
  const std::string partial = "0.0030000000000000001,0.99";  // a crash mid-row
  std::ofstream(path, std::ios::app | std::ios::binary) << partial;
  const std::string sidecar_before = ReadText(SidecarPath(path));

  {
    Journal journal(kReopenForAppend, path, SyncPolicy::kEveryRow);
    EXPECT_TRUE(journal.published());
    EXPECT_EQ(journal.rows(), 3);
    EXPECT_EQ(journal.truncated_bytes(), static_cast<long>(partial.size()));
    EXPECT_EQ(journal.previous_status(), "stopped: interrupted by the operator");
    ASSERT_EQ(journal.last_row().size(), 2u);
    EXPECT_EQ(journal.last_row()[0], 2e-3);
    EXPECT_EQ(journal.last_row()[1], 2.0 / 3.0);  // bit for bit
    EXPECT_EQ(journal.channels()[1].unit, "m");
    EXPECT_EQ(journal.sidecar()["status"], "stopped: interrupted by the operator");
    // The partial line is gone; the sidecar is untouched until a new row is committed.
    EXPECT_EQ(ReadText(path), before);
    EXPECT_EQ(ReadText(SidecarPath(path)), sidecar_before);

    for (long n = 3; n < 5; ++n) {
      const double row[] = {1e-3 * static_cast<double>(n), static_cast<double>(n) / 3.0};
      journal.Append(row);
      const nlohmann::json sidecar = ReadJson(SidecarPath(path));
      EXPECT_EQ(sidecar["status"], "running");
      EXPECT_FALSE(sidecar.contains("finish_time"));
    }
    journal.SetSidecarEntry("resumes", nlohmann::json::array({{{"step", 3}}}));
    EXPECT_EQ(ReadJson(SidecarPath(path))["resumes"][0]["step"], 3);
    journal.Finish({{"steps", 5}}, "completed");
  }
  // The same bytes as a run that was never interrupted.
  EXPECT_EQ(ReadText(path), uninterrupted);
  const nlohmann::json sidecar = ReadJson(SidecarPath(path));
  EXPECT_EQ(sidecar["status"], "completed");
  EXPECT_EQ(sidecar["rows"], 5);
  EXPECT_EQ(sidecar["resumes"][0]["step"], 3);
}

TEST(JournalLifecycle, ReopenedWithoutANewRowLeavesTheSidecarAlone) {
  const std::string dir = TempDir("reopen_idle");
  const std::string path = dir + "/run.csv";
  WriteStoppedJournal(path, 2);
  const std::string sidecar = ReadText(SidecarPath(path));
  { Journal journal(kReopenForAppend, path, SyncPolicy::kEveryRow); }
  EXPECT_EQ(ReadText(SidecarPath(path)), sidecar);
  EXPECT_EQ(FilesIn(dir), (std::vector<std::string>{"run.csv", "run.meta.json"}));
}

TEST(JournalLifecycle, ReopenNamesWhatIsWrong) {
  const std::string dir = TempDir("reopen_bad");
  const std::string path = dir + "/run.csv";
  auto expect_error = [&](const std::string& needle) {
    try {
      Journal journal(kReopenForAppend, path, SyncPolicy::kEveryRow);
      ADD_FAILURE() << "expected IoError containing " << needle;
    } catch (const IoError& e) {
      EXPECT_NE(std::string(e.what()).find(needle), std::string::npos) << e.what();
    }
  };
  expect_error("run.meta.json");  // no sidecar
  WriteStoppedJournal(path, 2);
  WriteText(path, "t,q2\n0,1\n");
  expect_error("run.csv:1: header 't,q2'");
  WriteText(path, "t,q1\n0,1\n0.001,x\n");
  expect_error("run.csv:3: the last row");
  WriteText(path, "t,q");
  expect_error("run.csv:1: the header line is incomplete");
  fs::remove(path);
  expect_error("cannot open the journal");
}

TEST(JournalLifecycle, SetSidecarEntryNeedsAPublishedJournal) {
  const std::string dir = TempDir("entry");
  Journal journal(dir + "/run.csv", kChannels, {}, SyncPolicy::kBatched);
  EXPECT_THROW(journal.SetSidecarEntry("note", 1), IoError);
}

TEST(StagesPath, SitsBesideTheJournal) {
  EXPECT_EQ(StagesPath("results/run.csv"), "results/run.stages.csv");
  EXPECT_EQ(StagesPath("run.csv"), "run.stages.csv");
  EXPECT_EQ(StagedPath("results/run.csv"), "results/run.csv.partial");
}

}  // namespace
}  // namespace hybridtest::io
