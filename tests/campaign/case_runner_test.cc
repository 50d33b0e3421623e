// A case run in process: its metrics against the same quantities computed from the journal it
// wrote (read back with io::LoadRun), its record, a failure, the error metric against the
// reference, and the summary's text.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>

#include "hybridtest/campaign/campaign_file.h"
#include "hybridtest/campaign/case_runner.h"
#include "hybridtest/campaign/summary.h"
#include "hybridtest/io/journal.h"
#include "hybridtest/io/run_reader.h"
#include "support/temp_dir.h"

namespace hybridtest::campaign {
namespace {

namespace fs = std::filesystem;
using test_support::FreshTempDir;
using test_support::WriteText;

Campaign MakeCampaign(const fs::path& dir, const std::string& k_b_values) {
  WriteText(dir / "base.yaml",
            "model:\n  name: rotor\n  blades: 3\nintegrator:\n  tableau: heun\n  dt: 0.001\n"
            "duration: 0.3\n");
  WriteText(dir / "c.yaml",
            "base: base.yaml\ngrid: {model.parameters.k_b: " + k_b_values + "}\n"
            "metrics: [max_abs(q1), max(q2), min(q2), rms(q1), final(u4), error(q1)]\n"
            "reference: c0-k_b=7200\nfigures: false\n");
  return LoadCampaign((dir / "c.yaml").string());
}

TEST(CaseRunner, MetricsEqualThoseOfTheJournalReadBack) {
  const fs::path dir = FreshTempDir("case_runner_metrics");
  const Campaign c = MakeCampaign(dir, "[7200, 6000]");
  const CaseResult r = RunCase(c, 1, (dir / "out").string(), {}, "test");
  ASSERT_EQ(r.status, "finished") << r.error;
  const io::RunData run = io::LoadRun(CaseJournal((dir / "out").string(), c, 1));
  ASSERT_EQ(run.num_rows(), 301);
  const Eigen::VectorXd q1 = run.Get("q1"), q2 = run.Get("q2"), u4 = run.Get("u4");
  double sum_sq = 0.0;
  for (Eigen::Index i = 0; i < q1.size(); ++i) sum_sq += q1[i] * q1[i];
  ASSERT_EQ(r.metrics.size(), 6u);
  EXPECT_EQ(r.metrics[0], q1.cwiseAbs().maxCoeff());
  EXPECT_EQ(r.metrics[1], q2.maxCoeff());
  EXPECT_EQ(r.metrics[2], q2.minCoeff());
  EXPECT_DOUBLE_EQ(r.metrics[3], std::sqrt(sum_sq / 301.0));
  EXPECT_EQ(r.metrics[4], u4[300]);
  EXPECT_TRUE(std::isnan(r.metrics[5]));  // filled once the reference has run
  EXPECT_GT(r.metrics[0], 0.0);
  // The record reads back as written.
  const auto back = ReadCaseResult((dir / "out").string(), c, 1);
  ASSERT_TRUE(back.has_value());
  EXPECT_EQ(back->status, "finished");
  EXPECT_EQ(back->metrics[0], r.metrics[0]);
  EXPECT_FALSE(ReadCaseResult((dir / "out").string(), c, 0).has_value());
}

TEST(CaseRunner, ErrorMetricIsTheLargestDifferenceFromTheReference) {
  const fs::path dir = FreshTempDir("case_runner_error");
  const Campaign c = MakeCampaign(dir, "[7200, 6000]");
  const std::string out = (dir / "out").string();
  std::vector<std::optional<CaseResult>> results{RunCase(c, 0, out, {}, "a"),
                                                 RunCase(c, 1, out, {}, "b")};
  FillErrorMetrics(c, out, results);
  EXPECT_EQ(results[0]->metrics[5], 0.0);
  const Eigen::VectorXd a = io::LoadRun(CaseJournal(out, c, 0)).Get("q1");
  const Eigen::VectorXd b = io::LoadRun(CaseJournal(out, c, 1)).Get("q1");
  EXPECT_EQ(results[1]->metrics[5], (a - b).cwiseAbs().maxCoeff());
  EXPECT_GT(results[1]->metrics[5], 0.0);
}

TEST(CaseRunner, AFailingCaseIsRecordedNotThrown) {
  const fs::path dir = FreshTempDir("case_runner_failing");
  const Campaign c = MakeCampaign(dir, "[7200, -5]");
  const CaseResult r = RunCase(c, 1, (dir / "out").string(), {}, "test");
  EXPECT_EQ(r.status, "failed");
  EXPECT_NE(r.error.find("k_b"), std::string::npos) << r.error;
  EXPECT_TRUE(fs::exists(fs::path(CaseDir((dir / "out").string(), c, 1)) / "case.json"));
  const auto back = ReadCaseResult((dir / "out").string(), c, 1);
  ASSERT_TRUE(back.has_value());
  EXPECT_EQ(back->error, r.error);
}

TEST(CaseRunner, AnUnfinishedAttemptIsMovedAsideNotDestroyed) {
  const fs::path dir = FreshTempDir("case_runner_aside");
  const Campaign c = MakeCampaign(dir, "[7200]");
  const fs::path case_dir = CaseDir((dir / "out").string(), c, 0);
  fs::create_directories(case_dir);
  WriteText(case_dir / "run.csv.partial", "t,q1\n0,0\n");
  const CaseResult r = RunCase(c, 0, (dir / "out").string(), {}, "test");
  EXPECT_EQ(r.status, "finished") << r.error;
  EXPECT_EQ(test_support::ReadText(case_dir / "interrupted-1" / "run.csv.partial"), "t,q1\n0,0\n");
}

// The real-time storey (ATS on the servo-hydraulic plant) for 0.25 s, with real_time.clock
// from the grid.
Campaign RealTimeCampaign(const fs::path& dir, const std::string& clocks) {
  WriteText(dir / "c.yaml",
            "base: " HYBRIDTEST_SOURCE_DIR "/examples/real-time/storey-ats.yaml\n"
            "command: run\nset: {duration: 0.25, real_time.lock_memory: false}\n"
            "grid: {real_time.clock: " + clocks + "}\n"
            "metrics: [max_abs(q1)]\nfigures: false\n");
  return LoadCampaign((dir / "c.yaml").string());
}

TEST(CaseRunner, ARealTimeCaseRunsPacedInVirtualTime) {
  const fs::path dir = FreshTempDir("case_runner_real_time");
  const Campaign c = RealTimeCampaign(dir, "[virtual]");
  const std::string out = (dir / "out").string();
  const CaseResult r = RunCase(c, 0, out, {}, "test");
  ASSERT_EQ(r.status, "finished") << r.error;
  // Paced by the session on the virtual clock: its deadlines are in the sidecar.
  const nlohmann::json rt = io::ReadSidecar(CaseJournal(out, c, 0))["statistics"]["real_time"];
  ASSERT_TRUE(rt.is_object()) << rt.dump();
  EXPECT_EQ(rt["clock"], "virtual");
  EXPECT_EQ(rt["ticks"], 256);
  EXPECT_EQ(rt["misses"], 0);
  EXPECT_TRUE(rt.contains("compensation")) << rt.dump();
  EXPECT_GT(r.metrics.at(0), 0.0);
}

TEST(CaseRunner, AWallClockCaseIsRefusedWithTheReasonAndTheWayOn) {
  const fs::path dir = FreshTempDir("case_runner_wall_clock");
  const Campaign c = RealTimeCampaign(dir, "[wall]");
  const std::string out = (dir / "out").string();
  const CaseResult r = RunCase(c, 0, out, {}, "test");
  EXPECT_EQ(r.status, "failed");
  EXPECT_NE(r.error.find("real_time.clock: wall"), std::string::npos) << r.error;
  EXPECT_NE(r.error.find("virtual time"), std::string::npos) << r.error;
  EXPECT_NE(r.error.find("hybridtest run"), std::string::npos) << r.error;
  EXPECT_FALSE(fs::exists(CaseJournal(out, c, 0)));  // refused before anything was written
}

// Issue 46's contract: a campaign of three real-time cases of the blade on two actuators
// (ATS on each, the built-in plant), in virtual time: each finishes paced with J1–J3 per
// actuator in its sidecar.
TEST(CaseRunner, ThreeTwoActuatorRealTimeCasesRun) {
  const fs::path dir = FreshTempDir("case_runner_two_actuators");
  WriteText(dir / "c.yaml",
            "base: " HYBRIDTEST_SOURCE_DIR "/examples/06_blade_two_actuators/real-time.yaml\n"
            "command: run\nset: {duration: 0.25, real_time.clock: virtual}\n"
            "grid: {substructures.blade1.transfer.window: [0.5, 1.0, 1.5]}\n"
            "metrics: [max_abs(q_flap)]\nfigures: false\n");
  const Campaign c = LoadCampaign((dir / "c.yaml").string());
  ASSERT_EQ(c.cases.size(), 3u);
  const std::string out = (dir / "out").string();
  for (int k = 0; k < 3; ++k) {
    const CaseResult r = RunCase(c, k, out, {}, "test");
    ASSERT_EQ(r.status, "finished") << r.error;
    const nlohmann::json rt =
        io::ReadSidecar(CaseJournal(out, c, k))["statistics"]["real_time"];
    EXPECT_EQ(rt["clock"], "virtual");
    EXPECT_EQ(rt["ticks"], 256);
    ASSERT_TRUE(rt["actuators"].is_array()) << rt.dump();
    ASSERT_EQ(rt["actuators"].size(), 2u) << rt.dump();
    for (const auto& a : rt["actuators"]) {
      EXPECT_TRUE(a["J2"].is_number()) << a.dump();
      EXPECT_LT(a["J2"].get<double>(), 5.0) << a.dump();  // [%]
    }
  }
}

TEST(Summary, RowsInCampaignOrderWithQuotedTextAndPendingCases) {
  const fs::path dir = FreshTempDir("case_runner_summary");
  const Campaign c = MakeCampaign(dir, "[7200, 6000, 5000]");
  CaseResult failed;
  failed.index = 1;
  failed.id = c.cases[1].id;
  failed.status = "failed";
  failed.error = "bad \"value\", see k_b";
  failed.duration = 0.5;
  failed.worker = "thread 0";
  failed.metrics.assign(6, std::nan(""));
  failed.metrics[0] = 0.1;
  const std::vector<std::optional<CaseResult>> results{std::nullopt, failed, std::nullopt};
  const std::string csv = SummaryCsv(c, results);
  EXPECT_EQ(csv,
            "case,model.parameters.k_b,status,duration_s,worker,max_abs(q1),max(q2),min(q2),"
            "rms(q1),final(u4),error(q1),error\n"
            "c0-k_b=7200,7200,pending,,,,,,,,,\n"
            "c1-k_b=6000,6000,failed,0.5,thread 0,0.1,,,,,,\"bad \"\"value\"\", see k_b\"\n"
            "c2-k_b=5000,5000,pending,,,,,,,,,\n");
}

}  // namespace
}  // namespace hybridtest::campaign
