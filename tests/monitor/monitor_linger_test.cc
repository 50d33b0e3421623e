// Issue 38's real-time contract: on a wall-clock run of examples/real-time/storey-ats.yaml (2 s
// of it) with --monitor-linger, /api/state carries the tick count, misses and J1–J3 (live
// while it runs, as recorded once it has ended), and the monitor keeps serving the final state
// after the run until Ctrl-C (the linger), which ends the process.
#include <csignal>

#include "monitor/example_config.h"
#include "monitor/monitor_process.h"

namespace hybridtest::testing {
namespace {

TEST(MonitorLinger, ARealTimeRunShowsItsTicksMissesAndJAndLingers) {
  const fs::path dir = ResumeTestDir("monitor_linger");
  const fs::path config = WriteExampleConfig(
      dir, "real-time", "storey-ats.yaml",
      {{"duration: 10.0", "duration: 2.0"}, {"lock_memory: true", "lock_memory: false"},
       {"hold_after_misses: 10", "hold_after_misses: 0"}},  // a busy test machine misses
      {"storey.model.yaml"});
  const fs::path csv = dir / "storey-ats.csv";
  MonitoredRun run({"run", config.string(), "--clock", "wall", "--out",
                    csv.string(), "--quiet", "--monitor", "127.0.0.1:0", "--monitor-no-token",
                    "--monitor-linger", "120"},
                   dir / "run.log");
  ASSERT_NE(run.port(), 0) << run.child().output();
  // While it runs: the paced loop's counts (or, on a slow machine, already the record).
  ASSERT_TRUE(run.WaitState([](const auto& s) {
    return s["realtime"]["available"].template get<bool>() && s["realtime"]["ticks"].is_number() &&
           s["realtime"]["ticks"].template get<long>() > 0;
  })) << run.child().output();
  // Ended (finished; or, where missed deadlines upset the compensator on a busy machine,
  // stopped by a safety limit): the record, and the server still answers (the linger).
  ASSERT_TRUE(run.WaitState([](const auto& s) {
    return s["status"] == "finished" || s["status"] == "stopped";
  })) << run.child().output();
  const nlohmann::json s = run.State();
  ASSERT_FALSE(s.is_null()) << "the monitor stopped serving when the run ended";
  const bool finished = s["status"] == "finished";
  const nlohmann::json& rt = s["realtime"];
  EXPECT_EQ(rt["source"], "recorded");
  if (finished) {
    EXPECT_EQ(rt["ticks"], 2048);
  }
  EXPECT_TRUE(rt["misses"].is_number());
  for (const char* j : {"J1_ms", "J2", "J3"}) EXPECT_TRUE(rt[j].is_number()) << j << rt.dump();
  const nlohmann::json sidecar = Sidecar(csv)["statistics"]["real_time"];
  EXPECT_EQ(rt["misses"], sidecar["misses"]);
  EXPECT_EQ(rt["J1_ms"], sidecar["J1_ms"]);
  EXPECT_EQ(run.child().WaitExit(0.5), -2) << "the process ended without lingering";
  run.child().Signal(SIGINT);  // ends the linger
  const int status = run.child().WaitExit(30.0);
  EXPECT_TRUE(finished ? status == 0 : status > 0) << status << run.child().output();
  fs::remove_all(dir);
}

}  // namespace
}  // namespace hybridtest::testing
