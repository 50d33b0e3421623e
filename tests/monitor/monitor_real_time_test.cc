// The monitor on a real-time run (wall clock, issue 32): Hold holds every actuator at the next
// tick and Continue resumes (the ideal plant then gives the journal of the run in virtual time,
// but for the lab-time columns); Stop ends the run with exit 130 and every committed row on
// disk; both are recorded in the sidecar's operator_actions, as on a lab-time run. The ticks
// go on from the Continue: the held time is neither a miss nor made up.
#include <fstream>

#include "monitor/monitor_process.h"
#include "support/temp_dir.h"

namespace hybridtest::testing {
namespace {

const std::string kToken = "monitor-real-time-token-0123456789";

class MonitorRealTime : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir_ = ResumeTestDir("monitor_real_time");
    test_support::WriteText(dir_ / "token", kToken + "\n");
    config_ = dir_ / "storey-ideal.yaml";
    std::ofstream(config_)
        << "model: {file: " << kSource << "/examples/real-time/storey.model.yaml}\n"
        << "integrator: {scheme: alpha-os, alpha: -0.05, dt: 0.0009765625}\n"
        << "duration: 3.0\n"
        << "real_time: {hold_after_misses: 0, lock_memory: false, queue: 16384}\n"
        << "substructures:\n  r1:\n    type: physical\n    initial_stiffness: 1.19e6\n"
        << "    transfer: {type: rt_plant, plant: ideal, specimen: {stiffness: 1.19e6}}\n"
        << "    safety: {stroke_min: -0.05, stroke_max: 0.05, max_increment: 0.002, "
           "force_soft: 40000, force_hard: 50000, timeout: 1}\n";
    reference_ = dir_ / "reference.csv";
    ASSERT_EQ(RunToEnd({"run", config_.string(), "--clock", "virtual", "--out",
                        reference_.string(), "--quiet"}, dir_ / "reference.log"), 0);
  }
  static void TearDownTestSuite() { fs::remove_all(dir_); }
  static std::vector<std::string> MonitoredArgs(const fs::path& csv) {
    return {"run", config_.string(), "--clock", "wall", "--out", csv.string(), "--quiet",
            "--monitor", "127.0.0.1:0", "--token-file", (dir_ / "token").string()};
  }
  static inline fs::path dir_, config_, reference_;
};

TEST_F(MonitorRealTime, HoldHoldsEveryActuatorAndContinueResumes) {
  const fs::path csv = dir_ / "held.csv";
  MonitoredRun run(MonitoredArgs(csv), dir_ / "held.log");
  ASSERT_NE(run.port(), 0) << run.child().output();
  ASSERT_TRUE(run.WaitState([](const auto& s) { return s["step"].template get<long>() > 200; }));
  ASSERT_EQ(run.Post("hold", kToken), 200);
  ASSERT_TRUE(run.WaitState([](const auto& s) { return s["status"] == "holding"; }))
      << run.child().output();
  std::this_thread::sleep_for(std::chrono::milliseconds(300));
  const long held_at = run.State()["step"].get<long>();
  std::this_thread::sleep_for(std::chrono::milliseconds(500));
  EXPECT_EQ(run.State()["step"].get<long>(), held_at) << "a tick was taken while holding";
  EXPECT_LT(held_at, 3072) << "the run ended before the hold";
  ASSERT_EQ(run.Post("continue", kToken), 200);
  ASSERT_EQ(run.child().WaitExit(60.0), 0) << run.child().output();
  EXPECT_EQ(WithoutLabTime(ReadLines(csv)), WithoutLabTime(ReadLines(reference_)));
  const nlohmann::json sidecar = Sidecar(csv);
  EXPECT_EQ(sidecar["status"], "completed");
  const auto& actions = sidecar["operator_actions"];
  ASSERT_EQ(actions.size(), 2u) << sidecar.dump();
  EXPECT_EQ(actions[0]["action"], "hold");
  EXPECT_EQ(actions[0]["step"].get<long>(), held_at);
  EXPECT_EQ(actions[1]["action"], "continue");
  // The held time was not counted as missed ticks.
  const auto& rt = sidecar["statistics"]["real_time"];
  EXPECT_EQ(rt["ticks"].get<long>(), 3072);
  RecordProperty("misses", std::to_string(rt["misses"].get<long>()));
}

TEST_F(MonitorRealTime, StopEndsTheRunWithEveryCommittedRowOnDisk) {
  const fs::path csv = dir_ / "stopped.csv";
  {
    MonitoredRun run(MonitoredArgs(csv), dir_ / "stopped.log");
    ASSERT_NE(run.port(), 0) << run.child().output();
    ASSERT_TRUE(run.WaitState([](const auto& s) { return s["step"].template get<long>() > 200; }));
    ASSERT_EQ(run.Post("stop", kToken), 200);
    ASSERT_EQ(run.child().WaitExit(60.0), 130) << run.child().output();
  }
  const nlohmann::json sidecar = Sidecar(csv);
  const auto lines = ReadLines(csv);
  EXPECT_EQ(static_cast<long>(lines.size()) - 1, sidecar["statistics"]["rows"].get<long>());
  EXPECT_LT(lines.size(), 3074u);
  EXPECT_EQ(sidecar["statistics"]["stop"]["kind"], "interrupted");
  ASSERT_EQ(sidecar["operator_actions"].size(), 1u) << sidecar.dump();
  EXPECT_EQ(sidecar["operator_actions"][0]["action"], "stop");
  // The rows kept are the reference run's rows.
  const auto reference = WithoutLabTime(ReadLines(reference_));
  const auto kept = WithoutLabTime(lines);
  ASSERT_LE(kept.size(), reference.size());
  EXPECT_TRUE(std::equal(kept.begin(), kept.end(), reference.begin()));
}

}  // namespace
}  // namespace hybridtest::testing
