// LoadRun: round trips through Journal, strict parsing with file:line errors, tolerance of a
// truncated last line, units from the sidecar or inferred from the names.
#include "hybridtest/io/run_reader.h"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <random>

#include "hybridtest/common/error.h"
#include "hybridtest/io/journal.h"
#include "support/temp_dir.h"

namespace hybridtest::io {
namespace {

namespace fs = std::filesystem;

using test_support::WriteText;

std::string TempDir(const std::string& name) {
  return test_support::FreshTempDir("reader_" + name).string();
}

std::string ErrorOf(const std::string& path) {
  try {
    LoadRun(path);
  } catch (const IoError& e) {
    return e.what();
  }
  return "";
}

TEST(RunReader, RoundTripsEveryDoubleBitForBit) {
  const std::string path = TempDir("roundtrip") + "/run.csv";
  const std::vector<Channel> channels = {
      {"t", "s", "simulated time"}, {"q4", "rad", "hub rotation"}, {"r1", "N", "blade 1 force"}};
  std::mt19937_64 rng(42);
  std::uniform_real_distribution<double> exponent(-300.0, 300.0);
  std::vector<std::vector<double>> rows;
  {
    Journal journal(path, channels, JournalMetadata{}, SyncPolicy::kBatched, 7);
    for (int i = 0; i < 100; ++i) {
      const double sign = (i % 2) ? -1.0 : 1.0;
      rows.push_back({i * 1e-3, sign * std::pow(10.0, exponent(rng)),
                      std::nextafter(0.1 * i, 1e9)});
      journal.Append(rows.back());
    }
    rows.push_back({std::numeric_limits<double>::denorm_min(),
                    std::numeric_limits<double>::max(), -0.0});
    journal.Append(rows.back());
    journal.Finish({{"steps", 101}}, "completed");
  }
  const RunData run = LoadRun(path);
  ASSERT_EQ(run.num_rows(), 101);
  ASSERT_EQ(run.num_channels(), 3);
  EXPECT_TRUE(run.warnings.empty());
  for (std::size_t i = 0; i < rows.size(); ++i) {
    for (std::size_t j = 0; j < 3; ++j) {
      EXPECT_EQ(run.values(static_cast<Eigen::Index>(i), static_cast<Eigen::Index>(j)),
                rows[i][j])
          << "row " << i << " column " << j;
    }
  }
  EXPECT_TRUE(std::signbit(run.values(100, 2)));
  // Units come from the sidecar, not from inference (which would say "m" for q4).
  EXPECT_EQ(run.Unit("q4"), "rad");
  EXPECT_EQ(run.Description("r1"), "blade 1 force");
  EXPECT_EQ(run.metadata["status"], "completed");
  EXPECT_EQ(run.metadata["statistics"]["steps"], 101);
  EXPECT_EQ(run.Get("r1")(5), rows[5][2]);
}

TEST(RunReader, NonFiniteValuesSurvive) {
  const std::string path = TempDir("nonfinite") + "/run.csv";
  {
    Journal journal(path, {{"t", "s", ""}, {"x", "", ""}}, {}, SyncPolicy::kEveryRow);
    const double row[] = {std::numeric_limits<double>::infinity(),
                          std::numeric_limits<double>::quiet_NaN()};
    journal.Append(row);
  }
  const RunData run = LoadRun(path);
  EXPECT_TRUE(std::isinf(run.values(0, 0)));
  EXPECT_TRUE(std::isnan(run.values(0, 1)));
}

TEST(RunReader, DropsATruncatedLastLineWithAWarning) {
  const std::string path = TempDir("truncated") + "/run.csv";
  WriteText(path, "t,q1\n0,1\n0.001,2\n0.002,3.00");
  const RunData run = LoadRun(path);
  EXPECT_EQ(run.num_rows(), 2);
  ASSERT_EQ(run.warnings.size(), 1u);
  EXPECT_NE(run.warnings[0].find(":4:"), std::string::npos) << run.warnings[0];
  EXPECT_TRUE(run.metadata.is_null());
}

TEST(RunReader, MalformedLinesNameFileAndLine) {
  const std::string dir = TempDir("malformed");
  WriteText(dir + "/fields.csv", "t,q1\n0,1\n0.001\n0.002,3\n");
  EXPECT_NE(ErrorOf(dir + "/fields.csv").find("fields.csv:3:"), std::string::npos)
      << ErrorOf(dir + "/fields.csv");
  WriteText(dir + "/number.csv", "t,q1\n0,1\n0.001,2\n0.002,3x\n");
  const std::string number = ErrorOf(dir + "/number.csv");
  EXPECT_NE(number.find("number.csv:4:"), std::string::npos) << number;
  EXPECT_NE(number.find("'q1'"), std::string::npos) << number;
  WriteText(dir + "/empty.csv", "");
  EXPECT_NE(ErrorOf(dir + "/empty.csv").find("empty.csv:1:"), std::string::npos);
  WriteText(dir + "/header.csv", "t,,q1\n");
  EXPECT_NE(ErrorOf(dir + "/header.csv").find("header.csv:1:"), std::string::npos);
  EXPECT_NE(ErrorOf(dir + "/missing.csv").find("missing.csv"), std::string::npos);
}

TEST(RunReader, HeaderOnlyGivesZeroRows) {
  const std::string path = TempDir("header_only") + "/run.csv";
  WriteText(path, "t,q1,u1\n");
  const RunData run = LoadRun(path);
  EXPECT_EQ(run.num_rows(), 0);
  EXPECT_EQ(run.values.cols(), 3);
  EXPECT_EQ(run.Get("u1").size(), 0);
}

TEST(RunReader, InfersUnitsWithoutSidecar) {
  const std::string path = TempDir("infer") + "/run.csv";
  WriteText(path, "t,q1,u2,r3,r1_command,r1_position,r1_force,r1_lab_time,energy\n"
                  "0,0,0,0,0,0,0,0,0\n");
  const RunData run = LoadRun(path);
  EXPECT_EQ(run.Unit("t"), "s");
  EXPECT_EQ(run.Unit("q1"), "m");
  EXPECT_EQ(run.Unit("u2"), "m/s");
  EXPECT_EQ(run.Unit("r3"), "N");
  EXPECT_EQ(run.Unit("r1_command"), "m");
  EXPECT_EQ(run.Unit("r1_position"), "m");
  EXPECT_EQ(run.Unit("r1_force"), "N");
  EXPECT_EQ(run.Unit("r1_lab_time"), "s");
  EXPECT_EQ(run.Unit("energy"), "");
  EXPECT_EQ(run.Description("u2"), "generalized speed 2");
}

TEST(RunReader, UnknownChannelListsTheAvailableOnes) {
  const std::string path = TempDir("unknown") + "/run.csv";
  WriteText(path, "t,q1\n0,1\n");
  const RunData run = LoadRun(path);
  EXPECT_EQ(run.Column("q1"), 1);
  EXPECT_EQ(run.Column("q2"), -1);
  try {
    run.Get("q2");
    FAIL() << "expected IoError";
  } catch (const IoError& e) {
    const std::string message = e.what();
    EXPECT_NE(message.find("'q2'"), std::string::npos) << message;
    EXPECT_NE(message.find("t, q1"), std::string::npos) << message;
  }
  EXPECT_THROW(run.Unit("q2"), IoError);
}

TEST(RunReader, MismatchedSidecarFallsBackToInference) {
  const std::string path = TempDir("mismatch") + "/run.csv";
  WriteText(path, "t,q1\n0,1\n");
  WriteText(SidecarPath(path), R"({"channels": [{"name": "t", "unit": "s"}]})");
  const RunData run = LoadRun(path);
  EXPECT_EQ(run.Unit("q1"), "m");
  EXPECT_EQ(run.warnings.size(), 1u);
  WriteText(SidecarPath(path), "{not json");
  EXPECT_NE(ErrorOf(path).find("meta.json"), std::string::npos);
}

TEST(ChannelNaming, Classifies) {
  EXPECT_EQ(ClassifyChannel("t").kind, ChannelKind::kTime);
  EXPECT_EQ(ClassifyChannel("q12").kind, ChannelKind::kCoordinate);
  EXPECT_EQ(ClassifyChannel("q12").index, 12);
  EXPECT_EQ(ClassifyChannel("u3").kind, ChannelKind::kSpeed);
  EXPECT_EQ(ClassifyChannel("r2").kind, ChannelKind::kRestoringForce);
  const ChannelClass physical = ClassifyChannel("blade_1_lab_time");
  EXPECT_EQ(physical.kind, ChannelKind::kPhysical);
  EXPECT_EQ(physical.slot, "blade_1");
  EXPECT_EQ(physical.field, "lab_time");
  EXPECT_EQ(ClassifyChannel("q").kind, ChannelKind::kOther);
  EXPECT_EQ(ClassifyChannel("q0").kind, ChannelKind::kOther);
  EXPECT_EQ(ClassifyChannel("qx").kind, ChannelKind::kOther);
  EXPECT_EQ(ClassifyChannel("_force").kind, ChannelKind::kOther);
  EXPECT_EQ(ClassifyChannel("time").kind, ChannelKind::kOther);
}

}  // namespace
}  // namespace hybridtest::io
