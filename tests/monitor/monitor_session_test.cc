// The monitor on a real Session (the dummy test on a loopback "bench"): the observer sees
// every committed row, never holds the run up (a ring of one frame drops, it does not wait),
// and the operator's Hold/Continue/Stop act between steps: Hold then Continue gives the same
// rows as a run that never held; Stop from a hold ends the run without another step.
#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <thread>
#include <vector>

#include "hybridtest/monitor/monitor_observer.h"
#include "hybridtest/monitor/operator_control.h"
#include "hybridtest/runner/stop_request.h"
#include "runner/dummy_spec.h"
#include "support/eventually.h"

namespace hybridtest::monitor {
namespace {

using runner::testing::DummySpec;
using test_support::Eventually;

// Keeps the committed journal rows.
class Rows final : public runner::SessionObserver {
 public:
  void OnCommit(const runner::CommitEvent& e) override {
    if (e.kind == runner::RowKind::kCommitted) rows.emplace_back(e.row.begin(), e.row.end());
  }
  std::vector<std::vector<double>> rows;
};

TEST(MonitorObserver, SeesEveryCommittedRowAndTheFinish) {
  MonitorState state(100000);
  MonitorObserver observer(state);
  runner::Session session(DummySpec(0.5));
  session.AddObserver(observer);
  ASSERT_EQ(session.Run().status, runner::SessionStatus::kFinished);
  const nlohmann::json j = state.StateJson();
  EXPECT_EQ(j["status"], "finished");
  EXPECT_EQ(j["frames"].get<long>(), session.statistics().rows);
  EXPECT_EQ(j["dropped_frames"], 0);
  EXPECT_DOUBLE_EQ(j["t"].get<double>(), session.statistics().sim_time);
  EXPECT_EQ(j["physical_evaluations"].get<long>(), session.statistics().physical_evaluations);
  EXPECT_EQ(j["identity"]["model"], "rotor");
  EXPECT_EQ(j["actuators"].size(), 1u);
  EXPECT_EQ(j["actuators"][0]["name"], "r1");
  EXPECT_EQ(j["actuators"][0]["substructure"], "r1");
  // d of the physical slot: the command minus p0 (the loopback's setup has p0 = 0).
  EXPECT_DOUBLE_EQ(j["slots"][0]["d"].get<double>(), j["actuators"][0]["command"].get<double>());
}

TEST(MonitorObserver, AFullRingDropsFramesInsteadOfWaiting) {
  MonitorState state;
  // One frame between drains, and drains once a minute: the run cannot wait for the reader.
  MonitorObserver observer(state, {1, 60.0});
  runner::Session session(DummySpec(0.5));
  session.AddObserver(observer);
  ASSERT_EQ(session.Run().status, runner::SessionStatus::kFinished);
  EXPECT_GT(observer.dropped(), 400);
  EXPECT_EQ(state.StateJson()["dropped_frames"].get<long>(), observer.dropped());
  EXPECT_EQ(state.status(), "finished");
}

// Steps `session` with `control` between the steps, as the command line does.
runner::StepResult RunWithControl(runner::Session& session, OperatorControl& control,
                                  const std::function<void(long)>& after_step = {}) {
  runner::StepResult result = session.Initialize();
  while (result.status == runner::SessionStatus::kWorking) {
    result = control.BetweenSteps(session);
    if (result.status != runner::SessionStatus::kWorking) break;
    result = session.Step();
    if (after_step) after_step(session.statistics().steps);
  }
  return result;
}

TEST(OperatorControl, HoldThenContinueGivesTheRowsOfARunThatNeverHeld) {
  Rows reference;
  {
    runner::Session session(DummySpec(0.3));
    session.AddObserver(reference);
    ASSERT_EQ(session.Run().status, runner::SessionStatus::kFinished);
  }
  MonitorState state;
  MonitorObserver observer(state);
  OperatorControl control(state);
  Rows rows;
  runner::Session session(DummySpec(0.3));
  session.AddObserver(observer);
  session.AddObserver(rows);
  std::atomic<long> steps_at_hold{-1};
  std::thread operator_thread([&] {
    ASSERT_TRUE(Eventually([&] { return state.status() == "running"; }));
    EXPECT_EQ(control.Request(OperatorAction::kContinue, "test").http_status, 409);
    EXPECT_EQ(control.Request(OperatorAction::kHold, "test").http_status, 200);
    EXPECT_EQ(control.Request(OperatorAction::kHold, "test").http_status, 409);
    ASSERT_TRUE(Eventually([&] { return state.status() == "holding"; }));
    std::this_thread::sleep_for(std::chrono::milliseconds(150));  // the last frame drained
    steps_at_hold = static_cast<long>(state.StateJson()["step"].get<long>());
    std::this_thread::sleep_for(std::chrono::milliseconds(200));
    EXPECT_EQ(state.status(), "holding");  // nothing stepped while holding
    EXPECT_EQ(state.StateJson()["step"].get<long>(), steps_at_hold.load());
    EXPECT_EQ(control.Request(OperatorAction::kContinue, "test").http_status, 200);
  });
  // Slow the first steps down so that the hold lands mid-run.
  const auto result = RunWithControl(session, control, [](long step) {
    if (step < 200) std::this_thread::sleep_for(std::chrono::milliseconds(2));
  });
  operator_thread.join();
  ASSERT_EQ(result.status, runner::SessionStatus::kFinished);
  EXPECT_GT(steps_at_hold.load(), 0);
  EXPECT_EQ(rows.rows, reference.rows);  // bit for bit, every channel
  const nlohmann::json actions = state.StateJson()["actions"];
  ASSERT_EQ(actions.size(), 2u);
  EXPECT_EQ(actions[0]["action"], "hold");
  EXPECT_EQ(actions[1]["action"], "continue");
  EXPECT_EQ(actions[0]["step"].get<long>(), steps_at_hold.load());
}

TEST(OperatorControl, StopFromAHoldEndsTheRunWithoutAnotherStep) {
  MonitorState state;
  MonitorObserver observer(state);
  OperatorControl control(state);
  runner::Session session(DummySpec(0.3));
  session.AddObserver(observer);
  long held_at = -1;
  std::thread operator_thread([&] {
    ASSERT_TRUE(Eventually([&] { return state.status() == "running"; }));
    control.Request(OperatorAction::kHold, "test");
    ASSERT_TRUE(Eventually([&] { return state.status() == "holding"; }));
    std::this_thread::sleep_for(std::chrono::milliseconds(150));  // the last frame drained
    held_at = state.StateJson()["step"].get<long>();
    EXPECT_EQ(control.Request(OperatorAction::kStop, "test").http_status, 200);
  });
  const auto result = RunWithControl(session, control, [](long step) {
    if (step < 200) std::this_thread::sleep_for(std::chrono::milliseconds(2));
  });
  operator_thread.join();
  EXPECT_EQ(result.status, runner::SessionStatus::kHeld);
  ASSERT_TRUE(session.error());  // what the command line rethrows (exit 130)
  EXPECT_THROW(std::rethrow_exception(session.error()), runner::Interrupted);
  EXPECT_EQ(session.statistics().steps, held_at);
  EXPECT_EQ(state.status(), "stopped");
  EXPECT_EQ(control.Request(OperatorAction::kHold, "test").http_status, 409);
}

}  // namespace
}  // namespace hybridtest::monitor
