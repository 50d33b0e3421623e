// The monitor's contract with the real binary (docs/monitor.md), on the ideal emulated bench
// (tests/data/resume-emulated-ideal.yaml, 10,001 rows):
//  - a Stop without the token gets 401/403 and the run goes on; Hold then Continue with the
//    token gives the journal of an uninterrupted run in t, q, u and r (and every other channel
//    but the bench's lab time), and the sidecar logs both with time and origin;
//  - a Stop with the token ends the run with exit 130, every committed row on disk, and
//    `hybridtest resume` completes it into the uninterrupted run's journal;
//  - `hybridtest monitor RUN.csv` serves a finished run whole, read-only.
#include "hybridtest/io/journal.h"
#include "monitor/monitor_process.h"
#include "support/listening_process.h"

namespace hybridtest::testing {
namespace {

const std::string kConfig = kSource + "/tests/data/resume-emulated-ideal.yaml";
const std::string kToken = "monitor-test-token-0123456789";

class MonitorCli : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir_ = ResumeTestDir("monitor_cli");
    test_support::WriteText(dir_ / "token", kToken + "\n");
    reference_ = dir_ / "reference.csv";
    ASSERT_EQ(RunToEnd({"run", kConfig, "--out", reference_.string(), "--quiet"},
                       dir_ / "reference.log"), 0);
  }
  static void TearDownTestSuite() { fs::remove_all(dir_); }
  static std::vector<std::string> MonitoredArgs(const fs::path& csv) {
    return {"run", kConfig, "--out", csv.string(), "--quiet", "--monitor", "127.0.0.1:0",
            "--token-file", (dir_ / "token").string()};
  }
  static inline fs::path dir_, reference_;
};

TEST_F(MonitorCli, HoldThenContinueGivesTheUninterruptedJournal) {
  const fs::path csv = dir_ / "held.csv";
  MonitoredRun run(MonitoredArgs(csv), dir_ / "held.log");
  ASSERT_NE(run.port(), 0) << run.child().output();
  ASSERT_TRUE(run.WaitState([](const auto& s) { return s["step"].template get<long>() > 200; }));
  // Without the token, or with a wrong one: refused, and the run goes on.
  EXPECT_EQ(run.Post("stop"), 401);
  EXPECT_EQ(run.Post("hold", "not-the-token"), 403);
  ASSERT_EQ(run.Post("hold", kToken), 200);
  ASSERT_TRUE(run.WaitState([](const auto& s) { return s["status"] == "holding"; }));
  std::this_thread::sleep_for(std::chrono::milliseconds(300));
  const long held_at = run.State()["step"].get<long>();
  std::this_thread::sleep_for(std::chrono::milliseconds(500));
  EXPECT_EQ(run.State()["step"].get<long>(), held_at) << "a step was taken while holding";
  ASSERT_EQ(run.Post("continue", kToken), 200);
  ASSERT_EQ(run.child().WaitExit(120.0), 0) << run.child().output();
  EXPECT_EQ(WithoutLabTime(ReadLines(csv)), WithoutLabTime(ReadLines(reference_)));
  const nlohmann::json sidecar = Sidecar(csv);
  EXPECT_EQ(sidecar["status"], "completed");
  const auto& actions = sidecar["operator_actions"];
  ASSERT_EQ(actions.size(), 2u);
  EXPECT_EQ(actions[0]["action"], "hold");
  EXPECT_EQ(actions[0]["step"].get<long>(), held_at);
  EXPECT_EQ(actions[1]["action"], "continue");
  EXPECT_NE(actions[0]["origin"].get<std::string>().find("127.0.0.1"), std::string::npos);
  EXPECT_FALSE(actions[0]["asked_at"].get<std::string>().empty());
}

TEST_F(MonitorCli, StopWithTheTokenEndsTheRunResumably) {
  const fs::path csv = dir_ / "stopped.csv";
  {
    MonitoredRun run(MonitoredArgs(csv), dir_ / "stopped.log");
    ASSERT_NE(run.port(), 0) << run.child().output();
    ASSERT_TRUE(run.WaitState([](const auto& s) { return s["step"].template get<long>() > 200; }));
    ASSERT_EQ(run.Post("stop", kToken), 200);
    ASSERT_EQ(run.child().WaitExit(60.0), 130) << run.child().output();
  }
  // Every committed row is on disk: the journal has the rows the sidecar counts.
  const nlohmann::json sidecar = Sidecar(csv);
  const auto lines = ReadLines(csv);
  EXPECT_EQ(static_cast<long>(lines.size()) - 1, sidecar["statistics"]["rows"].get<long>());
  EXPECT_LT(lines.size(), 10002u);
  EXPECT_EQ(sidecar["statistics"]["stop"]["kind"], "interrupted");
  ASSERT_EQ(sidecar["operator_actions"].size(), 1u);
  EXPECT_EQ(sidecar["operator_actions"][0]["action"], "stop");
  const auto [status, output] = Resume(csv, {}, dir_ / "resume.log");
  ASSERT_EQ(status, 0) << output;
  EXPECT_EQ(WithoutLabTime(ReadLines(csv)), WithoutLabTime(ReadLines(reference_)));
  EXPECT_EQ(Sidecar(csv)["operator_actions"].size(), 1u);  // kept across the resume
}

TEST_F(MonitorCli, TheFollowerServesAFinishedRunWhole) {
  test_support::ListeningProcess follower(
      {HYBRIDTEST_BINARY, "monitor", reference_.string(), "--listen", "127.0.0.1:0"},
      test_support::CurrentEnvironment(), R"(at http://127\.0\.0\.1:(\d+)/)",
      "hybridtest monitor");
  httplib::Client client("127.0.0.1", follower.port());
  auto res = client.Get("/api/state");
  ASSERT_TRUE(res);
  const auto state = nlohmann::json::parse(res->body);
  EXPECT_EQ(state["status"], "finished");
  EXPECT_EQ(state["frames"], 10001);
  EXPECT_DOUBLE_EQ(state["t"].get<double>(), 10.0);
  EXPECT_EQ(state["identity"]["mode"], "follow");
  EXPECT_DOUBLE_EQ(state["actuators"][0]["limits"]["force_hard"].get<double>(), 10000.0);
  const auto series = nlohmann::json::parse(client.Get("/api/series")->body);
  const auto& t = series["columns"]["t"];
  ASSERT_GT(t.size(), 100u);
  EXPECT_DOUBLE_EQ(t.front().get<double>(), 0.0);
  EXPECT_GT(t.back().get<double>(), 9.9);
  auto stop = client.Post("/api/stop", httplib::Headers{{"Authorization", "Bearer " + kToken}},
                          "", "text/plain");
  ASSERT_TRUE(stop);
  EXPECT_EQ(stop->status, 405);
  auto page = client.Get("/");
  ASSERT_TRUE(page);
  EXPECT_NE(page->body.find("hybridtest monitor"), std::string::npos);
  follower.Terminate(5.0);
}

}  // namespace
}  // namespace hybridtest::testing
