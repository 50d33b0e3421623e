// `hybridtest campaign` under `mpirun -n 3 --oversubscribe`: the contract campaign gives the
// same summary as local workers; a failing case does not stop the job; a rank that dies is
// reported and a rerun finishes its case. Skipped with a message where mpirun or an MPI-built
// hybridtest is missing.
#include <gtest/gtest.h>

#include <signal.h>

#include <filesystem>
#include <fstream>

#include "child_process.h"
#include "campaign_support.h"
#include "support/eventually.h"

namespace hybridtest::campaign_test {
namespace {

using test_support::FreshTempDir;
using test_support::ReadText;
using testing::RunCommand;

#define REQUIRE_MPIRUN(var, ranks)                     \
  std::string why;                                     \
  const std::string var = Mpirun(ranks, &why);         \
  if (var.empty()) GTEST_SKIP() << "skipped: " << why;

TEST(CampaignMpi, RotorWindUnderThreeRanksGivesTheSameSummaryAsLocalWorkers) {
  REQUIRE_MPIRUN(mpirun, 3);
  const fs::path dir = FreshTempDir("campaign_mpi_rotor_wind");
  const auto [a, a_output] = RunCommand(Campaign(kRotorWind, dir / "A", "--quiet"), 300);
  ASSERT_EQ(a, 0) << a_output;
  const auto [b, b_output] = RunCommand(mpirun + " " + Campaign(kRotorWind, dir / "B"), 300);
  ASSERT_EQ(b, 0) << b_output;
  const auto rows = ReadSummary(dir / "B" / "summary.csv");
  ASSERT_EQ(rows.size(), 24u);
  EXPECT_EQ(Comparable(rows), Comparable(ReadSummary(dir / "A" / "summary.csv")));
  // Rank 0 hands out the cases: ranks 1 and 2 ran them all.
  std::set<std::string> workers;
  for (const auto& row : rows) workers.insert(row.at("worker").substr(0, 6));
  EXPECT_EQ(workers, (std::set<std::string>{"rank 1", "rank 2"}));
  const auto sidecar = Sidecar(dir / "B");
  EXPECT_NE(sidecar["invocations"][0]["mode"].get<std::string>().find("mpi (3 ranks"),
            std::string::npos);
  // The journals are the same files as the local run's.
  for (const auto& entry : fs::directory_iterator(dir / "B" / "cases")) {
    EXPECT_EQ(ReadText(entry.path() / "run.csv"),
              ReadText(dir / "A" / "cases" / entry.path().filename() / "run.csv"))
        << entry.path();
  }
  fs::remove_all(dir);
}

TEST(CampaignMpi, AFailingCaseDoesNotStopTheJob) {
  REQUIRE_MPIRUN(mpirun, 3);
  const fs::path dir = FreshTempDir("campaign_mpi_failing");
  const fs::path file =
      WriteRotorCampaign(dir, "{model.parameters.k_b: [7200, -5, 9000, 8000]}", 0.2);
  const auto [status, output] = RunCommand(mpirun + " " + Campaign(file, dir / "out"), 120);
  EXPECT_EQ(status, 1) << output;
  const auto rows = ReadSummary(dir / "out" / "summary.csv");
  ASSERT_EQ(rows.size(), 4u);
  EXPECT_EQ(rows[1].at("status"), "failed");
  for (int i : {0, 2, 3}) EXPECT_EQ(rows[i].at("status"), "finished") << rows[i].at("case");
  fs::remove_all(dir);
}

// The pid of rank `rank` of the job whose command line names `marker`, or -1.
pid_t FindRank(int rank, const std::string& marker) {
  for (const auto& entry : fs::directory_iterator("/proc")) {
    const std::string name = entry.path().filename().string();
    if (name.find_first_not_of("0123456789") != std::string::npos) continue;
    const std::string cmdline = ReadText(entry.path() / "cmdline");
    const std::string environ = ReadText(entry.path() / "environ");
    if (cmdline.find(marker) == std::string::npos ||
        cmdline.find("campaign") == std::string::npos) {
      continue;
    }
    const std::string want = "OMPI_COMM_WORLD_RANK=" + std::to_string(rank);
    const auto at = environ.find(want);
    if (at != std::string::npos && (at == 0 || environ[at - 1] == '\0') &&
        (at + want.size() == environ.size() || environ[at + want.size()] == '\0')) {
      return static_cast<pid_t>(std::stol(name));
    }
  }
  return -1;
}

TEST(CampaignMpi, ADeadRankIsReportedAndARerunFinishesItsCase) {
  REQUIRE_MPIRUN(mpirun, 3);
  if (mpirun.find("--allow-run-as-root") == std::string::npos) {
    GTEST_SKIP() << "skipped: finding a rank's process needs Open MPI's environment";
  }
  const fs::path dir = FreshTempDir("campaign_mpi_dead_rank");
  const fs::path file = WriteRotorCampaign(
      dir, "{model.parameters.f_w: [10, 20, 30, 40, 50, 60, 70, 80, 90, 100, 110, 120, 130, 140, "
      "150, 160, 170, 180, 190, 200]}", 10.0);
  std::vector<std::string> args;
  std::istringstream words(mpirun + " " + Campaign(file, dir / "out"));
  for (std::string w; words >> w;) args.push_back(w);
  std::map<std::string, std::string> done;
  {
    Child job(args, dir / "job.log");
    ASSERT_TRUE(test_support::Eventually([&] { return DoneCases(dir / "out").size() >= 2; }))
        << job.output();
    const pid_t rank1 = FindRank(1, (dir / "out").string());
    ASSERT_GT(rank1, 0) << "no process of rank 1 found";
    ::kill(rank1, SIGKILL);
    EXPECT_NE(job.WaitExit(60), 0) << job.output();
    done = DoneCases(dir / "out");
  }
  ASSERT_LT(done.size(), 20u) << "the campaign ended before the rank was killed";
  const auto sidecar = Sidecar(dir / "out");
  EXPECT_EQ(sidecar["status"], "running");
  // A rerun (here with local workers) names what was running and finishes the rest.
  const auto [status, output] = RunCommand(Campaign(file, dir / "out"), 120);
  ASSERT_EQ(status, 0) << output;
  const auto& running = sidecar["progress"]["running"];
  if (!running.empty()) {
    EXPECT_NE(output.find("stopped while these cases ran"), std::string::npos) << output;
    EXPECT_NE(output.find(running[0]["case"].get<std::string>()), std::string::npos) << output;
  }
  EXPECT_EQ(RanLast(dir / "out").size() + done.size(), 20u);
  const auto rows = ReadSummary(dir / "out" / "summary.csv");
  ASSERT_EQ(rows.size(), 20u);
  for (const auto& row : rows) EXPECT_EQ(row.at("status"), "finished") << row.at("case");
  fs::remove_all(dir);
}

}  // namespace
}  // namespace hybridtest::campaign_test
