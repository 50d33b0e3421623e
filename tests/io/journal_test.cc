// Journal: the sidecar's content before and after Finish, atomic rewrites, the row format and
// the errors. Crash safety under SIGKILL is tested in tests/integration/journal_crash_test.cc.
#include "hybridtest/io/journal.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <array>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <random>
#include <fstream>
#include <sstream>

#include "hybridtest/common/error.h"
#include "hybridtest/common/version.h"
#include "hybridtest/io/csv.h"
#include "support/temp_dir.h"

namespace hybridtest::io {
namespace {

namespace fs = std::filesystem;

using test_support::ReadText;

std::string TempDir(const std::string& name) {
  return test_support::FreshTempDir("journal_" + name).string();
}

nlohmann::json ReadJson(const std::string& path) { return nlohmann::json::parse(ReadText(path)); }

JournalMetadata SampleMetadata() {
  JournalMetadata metadata;
  metadata.command = "simulate";
  metadata.config_path = "examples/rotor.yaml";
  metadata.config_text = "model: rotor\nintegrator:\n  dt: 0.001  # s\n";
  metadata.model = {{"name", "rotor"}};
  metadata.substructures = nlohmann::json::array({{{"slot", "r1"}, {"kind", "numerical"}}});
  metadata.extra = {{"note", "unit test"}};
  return metadata;
}

TEST(SidecarPath, ReplacesTheExtension) {
  EXPECT_EQ(SidecarPath("results/run.csv"), "results/run.meta.json");
  EXPECT_EQ(SidecarPath("results/run"), "results/run.meta.json");
  EXPECT_EQ(SidecarPath("a.b/run.csv"), "a.b/run.meta.json");
  EXPECT_EQ(SidecarPath("run.data.csv"), "run.data.meta.json");
}

TEST(Journal, WritesHeaderAndShortestRoundTripRows) {
  const std::string path = TempDir("rows") + "/run.csv";
  {
    Journal journal(path, {{"t", "s", ""}, {"q1", "m", ""}}, {}, SyncPolicy::kBatched, 2);
    const double row0[] = {0.0, 0.1};
    const double row1[] = {1e-3, -2.5e-12};
    journal.Append(row0);
    journal.Append(row1);
    EXPECT_EQ(journal.rows(), 2);
  }
  EXPECT_EQ(ReadText(path), "t,q1\n0,0.1\n0.001,-2.5e-12\n");
}

TEST(Journal, SidecarSaysRunningThenFinished) {
  const std::string path = TempDir("sidecar") + "/run.csv";
  const std::vector<Channel> channels = {{"t", "s", "simulated time"},
                                         {"q1", "m", "tip deflection of blade 1"}};
  Journal journal(path, channels, SampleMetadata(), SyncPolicy::kEveryRow);
  // Staged until the first row (journal_lifecycle_test.cc).
  const nlohmann::json running = ReadJson(StagedPath(SidecarPath(path)));
  EXPECT_EQ(running["format"], "hybridtest-journal/1");
  EXPECT_EQ(running["software_version"], kVersion);
  EXPECT_EQ(running["status"], "running");
  EXPECT_EQ(running["command"], "simulate");
  EXPECT_EQ(running["config_path"], "examples/rotor.yaml");
  EXPECT_EQ(running["config"], SampleMetadata().config_text);
  EXPECT_EQ(running["model"]["name"], "rotor");
  EXPECT_EQ(running["substructures"][0]["slot"], "r1");
  EXPECT_EQ(running["extra"]["note"], "unit test");
  ASSERT_EQ(running["channels"].size(), 2u);
  EXPECT_EQ(running["channels"][1]["name"], "q1");
  EXPECT_EQ(running["channels"][1]["unit"], "m");
  EXPECT_EQ(running["channels"][1]["description"], "tip deflection of blade 1");
  EXPECT_FALSE(running.contains("statistics"));
  // ISO-8601 UTC: 2024-05-01T12:34:56Z
  const std::string start = running["start_time"];
  ASSERT_EQ(start.size(), 20u) << start;
  EXPECT_EQ(start[10], 'T');
  EXPECT_EQ(start.back(), 'Z');

  const double row[] = {0.0, 1.0};
  journal.Append(row);
  EXPECT_EQ(ReadJson(SidecarPath(path)), running);
  journal.Finish({{"steps", 1}, {"physical_evaluations", 0}}, "stopped: force limit");
  const nlohmann::json finished = ReadJson(SidecarPath(path));
  EXPECT_EQ(finished["status"], "stopped: force limit");
  EXPECT_EQ(finished["statistics"]["steps"], 1);
  EXPECT_EQ(finished["rows"], 1);
  EXPECT_EQ(finished["start_time"], start);
  // The atomic rewrite leaves no temporary file behind.
  EXPECT_FALSE(fs::exists(SidecarPath(path) + ".tmp"));
  EXPECT_THROW(journal.Append(row), IoError);
}

TEST(Journal, DestructorWithoutFinishMarksTheRunAborted) {
  const std::string path = TempDir("aborted") + "/run.csv";
  {
    Journal journal(path, {{"t", "s", ""}}, {}, SyncPolicy::kBatched);
    const double row[] = {0.5};
    journal.Append(row);
  }
  const nlohmann::json sidecar = ReadJson(SidecarPath(path));
  EXPECT_EQ(sidecar["status"].get<std::string>().rfind("aborted", 0), 0u);
  EXPECT_EQ(ReadText(path), "t\n0.5\n");
}

TEST(Journal, MissingDirectoryNamesThePath) {
  const std::string path = TempDir("missing") + "/no/such/dir/run.csv";
  try {
    Journal journal(path, {{"t", "s", ""}}, {}, SyncPolicy::kBatched);
    FAIL() << "expected IoError";
  } catch (const IoError& e) {
    const std::string message = e.what();
    EXPECT_NE(message.find("no/such/dir"), std::string::npos) << message;
    EXPECT_NE(message.find("No such file or directory"), std::string::npos) << message;
  }
}

TEST(Journal, RejectsBadChannelsAndRows) {
  const std::string dir = TempDir("bad");
  EXPECT_THROW(Journal(dir + "/a.csv", {}, {}, SyncPolicy::kBatched), IoError);
  EXPECT_THROW(Journal(dir + "/b.csv", {{"t", "s", ""}, {"t", "s", ""}}, {},
                       SyncPolicy::kBatched),
               IoError);
  EXPECT_THROW(Journal(dir + "/c.csv", {{"a,b", "", ""}}, {}, SyncPolicy::kBatched), IoError);
  EXPECT_THROW(Journal(dir + "/d.csv", {{"t", "s", ""}}, {}, SyncPolicy::kBatched, 0), IoError);
  Journal journal(dir + "/e.csv", {{"t", "s", ""}, {"q1", "m", ""}}, {}, SyncPolicy::kBatched);
  const double short_row[] = {1.0};
  EXPECT_THROW(journal.Append(short_row), IoError);
  EXPECT_EQ(journal.rows(), 0);
}

TEST(Csv, NumbersAreTheShortestTextThatReadsBackBitForBit) {
  for (const double value : {0.0, 1.0, -0.1, 1.0 / 3.0, 6.02214076e23, 1e-310, 123456789.0}) {
    std::string ours;
    AppendCsvNumber(value, ours);
    char seventeen[40];
    std::snprintf(seventeen, sizeof seventeen, "%.17g", value);
    EXPECT_LE(ours.size(), std::strlen(seventeen)) << ours;
    EXPECT_EQ(ParseCsvNumber(ours), value);
    EXPECT_EQ(ParseCsvNumber(seventeen), value);  // files written before read the same
  }
  std::string s;
  AppendCsvNumber(0.1, s);
  EXPECT_EQ(s, "0.1");
  // Random bit patterns (finite ones): the text reads back to the same bits.
  std::mt19937_64 rng(11);
  for (int i = 0; i < 100000; ++i) {
    const std::uint64_t bits = rng();
    double value;
    std::memcpy(&value, &bits, sizeof value);
    if (!std::isfinite(value)) continue;
    std::string text;
    AppendCsvNumber(value, text);
    const auto back = ParseCsvNumber(text);
    ASSERT_TRUE(back.has_value()) << text;
    std::uint64_t back_bits;
    std::memcpy(&back_bits, &*back, sizeof back_bits);
    ASSERT_EQ(back_bits, bits) << text;
  }
  EXPECT_FALSE(ParseCsvNumber("").has_value());
  EXPECT_FALSE(ParseCsvNumber("1.0.0").has_value());
  EXPECT_FALSE(ParseCsvNumber("abc").has_value());
  EXPECT_EQ(ParseCsvNumber(" +2.5 "), 2.5);
}

// Rows of a numerical run are held in memory after the first (which publishes the journal)
// until a block is full, Flush() or Finish(); then every row is in the file, bit-exact.
TEST(Journal, BufferedRowsReachTheFileOnFlushAndFinish) {
  const std::string path = TempDir("buffered") + "/run.csv";
  Journal journal(path, {{"t", "s", ""}, {"q1", "m", ""}}, {}, SyncPolicy::kBuffered);
  std::vector<std::array<double, 2>> rows;
  std::mt19937_64 rng(5);
  std::normal_distribution<double> normal;
  for (int i = 0; i < 5; ++i) rows.push_back({1e-3 * i, normal(rng)});
  journal.Append(rows[0]);
  EXPECT_TRUE(journal.published());
  const auto published_size = fs::file_size(path);
  for (int i = 1; i < 5; ++i) journal.Append(rows[i]);
  EXPECT_EQ(journal.rows(), 5);
  EXPECT_EQ(fs::file_size(path), published_size);  // rows 2..5 are still in memory
  journal.Flush();
  EXPECT_GT(fs::file_size(path), published_size);
  const auto flushed_size = fs::file_size(path);
  journal.Flush(/*sync=*/true);  // nothing pending: no change
  EXPECT_EQ(fs::file_size(path), flushed_size);
  // Enough rows to fill blocks: they are written without a Flush.
  for (int i = 0; i < 20000; ++i) {
    rows.push_back({1.0 + 1e-3 * i, normal(rng)});
    journal.Append(rows.back());
  }
  EXPECT_GT(fs::file_size(path), flushed_size + kJournalBlockBytes);
  journal.Finish({}, "completed");
  // Read back: every value bit for bit.
  std::istringstream in(ReadText(path));
  std::string line;
  std::getline(in, line);
  EXPECT_EQ(line, "t,q1");
  std::size_t i = 0;
  while (std::getline(in, line)) {
    ASSERT_LT(i, rows.size());
    const auto fields = SplitCsvLine(line);
    ASSERT_EQ(fields.size(), 2u);
    EXPECT_EQ(ParseCsvNumber(fields[0]), rows[i][0]);
    EXPECT_EQ(ParseCsvNumber(fields[1]), rows[i][1]);
    ++i;
  }
  EXPECT_EQ(i, rows.size());
  EXPECT_EQ(ReadJson(SidecarPath(path))["rows"], static_cast<long>(rows.size()));
}

// A buffered journal destroyed without Finish (an exception unwound the run) still writes
// what it holds.
TEST(Journal, BufferedRowsAreWrittenByTheDestructor) {
  const std::string path = TempDir("buffered_dtor") + "/run.csv";
  {
    Journal journal(path, {{"t", "s", ""}}, {}, SyncPolicy::kBuffered);
    for (int i = 0; i < 10; ++i) {
      const double row[] = {0.5 * i};
      journal.Append(row);
    }
  }
  EXPECT_EQ(ReadText(path), "t\n0\n0.5\n1\n1.5\n2\n2.5\n3\n3.5\n4\n4.5\n");
}

}  // namespace
}  // namespace hybridtest::io
