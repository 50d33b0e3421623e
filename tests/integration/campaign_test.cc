// `hybridtest campaign` with local workers: the contract campaign (24 cases of the paper's
// rotor; each case's journal equals `simulate` of its config bit for bit; serial and parallel
// give the same summary), reruns that run exactly the missing cases, a failing case, a
// killed campaign, and a folder that belongs to another campaign.
#include <gtest/gtest.h>

#include <signal.h>

#include <filesystem>

#include "child_process.h"
#include "campaign_support.h"
#include "support/eventually.h"

namespace hybridtest::campaign_test {
namespace {

using test_support::FreshTempDir;
using test_support::ReadText;
using testing::RunCommand;

class RotorWind : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir_ = new fs::path(FreshTempDir("campaign_rotor_wind"));
    const auto [status, output] = RunCommand(Campaign(kRotorWind, *dir_ / "A", "--workers 2"), 300);
    status_ = status;
    output_ = new std::string(output);
  }
  static void TearDownTestSuite() {
    fs::remove_all(*dir_);
    delete dir_;
    delete output_;
  }
  static fs::path* dir_;
  static std::string* output_;
  static int status_;
};
fs::path* RotorWind::dir_ = nullptr;
std::string* RotorWind::output_ = nullptr;
int RotorWind::status_ = -1;

TEST_F(RotorWind, TwentyFourCasesFinishWithTheirMetrics) {
  ASSERT_EQ(status_, 0) << *output_;
  const auto rows = ReadSummary(*dir_ / "A" / "summary.csv");
  ASSERT_EQ(rows.size(), 24u);
  std::set<std::string> f_w, k_b;
  for (const auto& row : rows) {
    EXPECT_EQ(row.at("status"), "finished") << row.at("case");
    f_w.insert(row.at("model.parameters.f_w"));
    k_b.insert(row.at("model.parameters.blade1.k_b"));
    EXPECT_GT(std::stod(row.at("max_abs(q1)")), 0.0);
  }
  EXPECT_EQ(f_w.size(), 8u);
  EXPECT_EQ(k_b.size(), 3u);
  // The reference case's error against itself is 0; a stiffer blade 1 deflects less under
  // the same wind (the physics the metrics must show).
  const auto at = [&](const std::string& w, const std::string& k) {
    for (const auto& row : rows) {
      if (row.at("model.parameters.f_w") == w && row.at("model.parameters.blade1.k_b") == k) {
        return row;
      }
    }
    return Row{};
  };
  EXPECT_EQ(at("100", "7200").at("error(q1)"), "0");
  EXPECT_GT(std::stod(at("100", "5250").at("error(q1)")), 0.0);
  EXPECT_GT(std::stod(at("150", "5250").at("max_abs(q1)")),
            std::stod(at("150", "9000").at("max_abs(q1)")));
  const auto sidecar = Sidecar(*dir_ / "A");
  EXPECT_EQ(sidecar["status"], "completed");
  EXPECT_EQ(sidecar["progress"]["done"], 24);
  EXPECT_FALSE(sidecar["campaign"]["sha256"].get<std::string>().empty());
}

TEST_F(RotorWind, EachJournalEqualsSimulateOfTheCaseConfigBitForBit) {
  ASSERT_EQ(status_, 0) << *output_;
  int compared = 0;
  for (const auto& entry : fs::directory_iterator(*dir_ / "A" / "cases")) {
    const fs::path simulated = *dir_ / ("sim-" + entry.path().filename().string() + ".csv");
    const auto [status, output] = RunCommand(kBinary + " simulate '" +
                                             (entry.path() / "config.yaml").string() +
                                             "' --quiet --out '" + simulated.string() + "'");
    ASSERT_EQ(status, 0) << output;
    const std::string journal = ReadText(entry.path() / "run.csv");
    ASSERT_FALSE(journal.empty());
    EXPECT_EQ(journal, ReadText(simulated)) << entry.path();
    ++compared;
  }
  EXPECT_EQ(compared, 24);
}

TEST_F(RotorWind, SerialGivesTheSameSummary) {
  ASSERT_EQ(status_, 0) << *output_;
  const auto [status, output] = RunCommand(Campaign(kRotorWind, *dir_ / "serial",
                                                    "--workers 1 --quiet"), 300);
  ASSERT_EQ(status, 0) << output;
  EXPECT_EQ(Comparable(ReadSummary(*dir_ / "serial" / "summary.csv")),
            Comparable(ReadSummary(*dir_ / "A" / "summary.csv")));
}

TEST_F(RotorWind, DeletingTwoCasesRerunsExactlyThoseTwo) {
  ASSERT_EQ(status_, 0) << *output_;
  const fs::path copy = *dir_ / "A-copy";
  fs::copy(*dir_ / "A", copy, fs::copy_options::recursive);
  const std::set<std::string> deleted{"c03-f_w=50-blade1.k_b=5250", "c20-f_w=175-blade1.k_b=9000"};
  for (const auto& id : deleted) ASSERT_TRUE(fs::remove_all(copy / "cases" / id) > 0);
  const auto before = DoneCases(copy);
  const auto [status, output] = RunCommand(Campaign(kRotorWind, copy), 300);
  ASSERT_EQ(status, 0) << output;
  EXPECT_EQ(RanLast(copy), deleted);
  EXPECT_NE(output.find("ran 2, skipped 22"), std::string::npos) << output;
  const auto after = DoneCases(copy);
  for (const auto& [id, text] : before) EXPECT_EQ(after.at(id), text) << id;  // untouched
  EXPECT_EQ(Comparable(ReadSummary(copy / "summary.csv")),
            Comparable(ReadSummary(*dir_ / "A" / "summary.csv")));
}

TEST(Campaign, AFailingCaseIsRecordedAndTheOthersFinish) {
  const fs::path dir = FreshTempDir("campaign_failing");
  const fs::path file = WriteRotorCampaign(dir, "{model.parameters.k_b: [7200, -5, 9000]}", 0.2);
  const auto [status, output] = RunCommand(Campaign(file, dir / "out", "--workers 2"));
  EXPECT_EQ(status, 1) << output;
  const auto rows = ReadSummary(dir / "out" / "summary.csv");
  ASSERT_EQ(rows.size(), 3u);
  EXPECT_EQ(rows[0].at("status"), "finished");
  EXPECT_EQ(rows[1].at("status"), "failed");
  EXPECT_NE(rows[1].at("error").find("k_b"), std::string::npos) << rows[1].at("error");
  EXPECT_EQ(rows[1].at("max_abs(q1)"), "");
  EXPECT_EQ(rows[2].at("status"), "finished");
  EXPECT_EQ(Sidecar(dir / "out")["status"], "completed with failures");
  // A rerun keeps the record: the failed case is not run again (move its folder to retry).
  const auto [again, again_output] = RunCommand(Campaign(file, dir / "out"));
  EXPECT_EQ(again, 1);
  EXPECT_TRUE(RanLast(dir / "out").empty()) << again_output;
  fs::remove_all(dir);
}

TEST(Campaign, AKilledCampaignRerunFinishesOnlyTheMissingCases) {
  const fs::path dir = FreshTempDir("campaign_killed");
  const fs::path file = WriteRotorCampaign(
      dir, "{model.parameters.f_w: [10, 20, 30, 40, 50, 60, 70, 80, 90, 100, 110, 120, 130, 140, "
      "150, 160, 170, 180, 190, 200]}", 10.0);
  std::map<std::string, std::string> done;
  {
    Child child({kBinary, "campaign", file.string(), "--out", (dir / "out").string(),
                 "--workers", "1"}, dir / "first.log");
    ASSERT_TRUE(test_support::Eventually([&] { return DoneCases(dir / "out").size() >= 3; }))
        << child.output();
    child.Signal(SIGKILL);
    child.WaitExit(10);
    done = DoneCases(dir / "out");
  }
  ASSERT_LT(done.size(), 20u) << "the campaign ended before it was killed";
  EXPECT_FALSE(fs::exists(dir / "out" / "summary.csv"));
  const auto [status, output] = RunCommand(Campaign(file, dir / "out"), 120);
  ASSERT_EQ(status, 0) << output;
  std::set<std::string> missing;
  for (const auto& entry : fs::directory_iterator(dir / "out" / "cases")) {
    if (!done.count(entry.path().filename().string())) {
      missing.insert(entry.path().filename().string());
    }
  }
  EXPECT_EQ(RanLast(dir / "out"), missing);
  EXPECT_EQ(missing.size() + done.size(), 20u);
  const auto after = DoneCases(dir / "out");
  for (const auto& [id, text] : done) EXPECT_EQ(after.at(id), text) << id;
  const auto rows = ReadSummary(dir / "out" / "summary.csv");
  ASSERT_EQ(rows.size(), 20u);
  for (const auto& row : rows) EXPECT_EQ(row.at("status"), "finished") << row.at("case");
  fs::remove_all(dir);
}

TEST(Campaign, RunAndPlanCasesOnAnEmulatedBench) {
  const fs::path dir = FreshTempDir("campaign_run_plan");
  for (const std::string command : {"run", "plan"}) {
    test_support::WriteText(
        dir / (command + ".yaml"),
        "base: " + kSource + "/examples/rotor/emulated-fast.yaml\ncommand: " + command +
            "\nset: {duration: 1.0}\ngrid: {model.parameters.f_w: [50, 100]}\n"
            "metrics: [max_abs(r1_force)]\nfigures: false\n");
    const auto [status, output] =
        RunCommand(Campaign(dir / (command + ".yaml"), dir / command, "--quiet"), 300);
    ASSERT_EQ(status, 0) << output;
    const auto rows = ReadSummary(dir / command / "summary.csv");
    ASSERT_EQ(rows.size(), 2u);
    for (const auto& row : rows) {
      EXPECT_EQ(row.at("status"), "finished") << row.at("error");
      const fs::path case_dir = dir / command / "cases" / row.at("case");
      if (command == "run") {
        EXPECT_GT(std::stod(row.at("max_abs(r1_force)")), 0.0);
        EXPECT_TRUE(fs::exists(case_dir / "run.stages.csv"));
      } else {
        EXPECT_FALSE(row.at("recommendation").empty());
        EXPECT_GT(std::stod(row.at("evaluations")), 0.0);
        EXPECT_FALSE(fs::exists(case_dir / "run.csv"));  // plan runs in memory
      }
    }
  }
  fs::remove_all(dir);
}

TEST(Campaign, AFolderOfAnotherCampaignIsRefused) {
  const fs::path dir = FreshTempDir("campaign_other");
  const fs::path file = WriteRotorCampaign(dir, "{model.parameters.f_w: [50]}", 0.1);
  ASSERT_EQ(RunCommand(Campaign(file, dir / "out")).first, 0);
  WriteRotorCampaign(dir, "{model.parameters.f_w: [60]}", 0.1);
  const auto [status, output] = RunCommand(Campaign(file, dir / "out"));
  EXPECT_EQ(status, 2) << output;
  EXPECT_NE(output.find("another campaign"), std::string::npos) << output;
  EXPECT_TRUE(fs::exists(dir / "out" / "cases" / "c0-f_w=50" / "run.csv"));
  fs::remove_all(dir);
}

}  // namespace
}  // namespace hybridtest::campaign_test
