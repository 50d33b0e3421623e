// Issue 46's contract for the monitor: `/api/state` of a wall-clock run of two actuators carries
// the ticks, the misses and J1–J3 of each actuator as numbers while it runs, and Hold and Stop
// act within one tick. The run is examples/real-time/coupler-ats.yaml (two actuators on one
// coupled specimen, ATS on each) on the ideal plant (so that a late tick on a loaded machine
// cannot make it unstable), 2 s of it, paced on the wall clock, with the monitor's server on
// 127.0.0.1. The actions are posted over HTTP from the stepping thread at known committed
// steps, so that the assertions are on the step counts the run records, never on wall time:
// a hold asked at step k is applied at k (no commit while held), a stop asked at step k ends
// the run with k steps (no commit after it).
#include <gtest/gtest.h>

#include "hybridtest/io/run_spec_yaml.h"
#include "hybridtest/monitor/monitor_observer.h"
#include "hybridtest/monitor/monitor_server.h"
#include "hybridtest/monitor/operator_control.h"
#include "hybridtest/runner/paced_loop.h"
#include "monitor/example_config.h"
#include "support/eventually.h"

// After Eigen: <resolv.h>, which httplib includes, defines _res.
#include <httplib.h>

#include <atomic>
#include <thread>

namespace hybridtest::testing {
namespace {

const std::string kToken = "monitor-two-actuators-token-0123456789";
constexpr long kSnapshotAt = 1100;  // after 1 s of ticks: J1 has its window
constexpr long kHoldAt = 1200;
constexpr long kStopAt = 1300;

int Post(httplib::Client& client, const std::string& path) {
  auto res = client.Post(path.c_str(), httplib::Headers{{"Authorization", "Bearer " + kToken}},
                         "", "text/plain");
  return res ? res->status : -1;
}

// On the stepping thread (real_time_safe): takes /api/state at kSnapshotAt, once the monitor
// holds that step, and posts Hold at kHoldAt and Stop at kStopAt.
class Operator final : public runner::SessionObserver {
 public:
  Operator(monitor::MonitorState& state, int port) : state_(state), client_("127.0.0.1", port) {
    client_.set_connection_timeout(5);
    client_.set_read_timeout(5);
  }
  void OnCommit(const runner::CommitEvent& e) override {
    if (e.kind != runner::RowKind::kCommitted) return;
    last_step = e.step;
    if (e.step == kSnapshotAt) {
      for (int i = 0; i < 2000 && state_.frames() <= kSnapshotAt; ++i) {
        std::this_thread::sleep_for(std::chrono::milliseconds(5));
      }
      if (auto res = client_.Get("/api/state")) live = nlohmann::json::parse(res->body);
    }
    if (e.step == kHoldAt) hold_status = Post(client_, "/api/hold");
    if (e.step == kStopAt) stop_status = Post(client_, "/api/stop");
  }
  bool real_time_safe() const override { return true; }  // a test: it may wait

  std::atomic<long> last_step{-1};
  nlohmann::json live;
  int hold_status = 0, stop_status = 0;

 private:
  monitor::MonitorState& state_;
  httplib::Client client_;
};

TEST(MonitorTwoActuatorsWallClock, TheStateCarriesEachActuatorsCriteriaAndHoldAndStopActAtOnce) {
  const fs::path dir = ResumeTestDir("monitor_two_actuators_wall");
  const fs::path config = WriteExampleConfig(
      dir, "real-time", "coupler-ats.yaml",
      {{"duration: 10.0", "duration: 2.0"},
       {"hold_after_misses: 10", "hold_after_misses: 0"},
       {"lock_memory: true", "lock_memory: false"},
       {"delay: 0.022 .*", "delay: 0.0"},
       {"plant: servo_hydraulic.*", "plant: ideal"}},
      {"coupler.model.yaml"});
  io::RunSpec spec = io::LoadRunSpec(config.string());
  spec.output.files = false;
  spec.real_time.clock = "wall";
  runner::Session session(std::move(spec));
  monitor::MonitorState state(100000);
  monitor::MonitorObserver observer(state);
  monitor::OperatorControl control(state);
  monitor::MonitorServerOptions options;
  options.token = kToken;
  monitor::MonitorServer server(state, &control, options);
  server.Start();
  session.AddObserver(observer);
  session.SetBetweenSteps([&](runner::Session& s) { return control.BetweenSteps(s); });
  Operator op(state, server.port());
  session.AddObserver(op);

  // The operator at the page: continues once the run holds, after checking that nothing was
  // committed since the hold was asked.
  long steps_when_held = -1;
  std::thread page([&] {
    httplib::Client client("127.0.0.1", server.port());
    client.set_connection_timeout(5);
    client.set_read_timeout(5);
    if (!test_support::Eventually([&] { return state.status() == "holding"; })) {
      ADD_FAILURE() << "the run did not hold";
      Post(client, "/api/stop");  // whatever happened, the run ends
      return;
    }
    steps_when_held = op.last_step.load();
    EXPECT_EQ(Post(client, "/api/continue"), 200);
  });
  const runner::StepResult result = session.Run();
  page.join();
  server.Stop();

  // While it ran: ticks, misses and J1–J3 of each actuator, as numbers.
  ASSERT_TRUE(op.live.is_object()) << "no /api/state at step " << kSnapshotAt;
  const nlohmann::json& rt = op.live["realtime"];
  ASSERT_TRUE(rt["available"].get<bool>()) << rt.dump();
  EXPECT_EQ(rt["source"], "live");
  EXPECT_EQ(rt["clock"], "wall");
  ASSERT_TRUE(rt["ticks"].is_number()) << rt.dump();
  EXPECT_EQ(rt["ticks"].get<long>(), kSnapshotAt);
  ASSERT_TRUE(rt["misses"].is_number()) << rt.dump();
  EXPECT_GE(rt["misses"].get<long>(), 0);
  ASSERT_EQ(rt["actuators"].size(), 2u) << rt.dump();
  for (int k = 0; k < 2; ++k) {
    const nlohmann::json& a = rt["actuators"][std::size_t(k)];
    const std::string name = "frame_a" + std::to_string(k + 1);
    EXPECT_EQ(a["name"], name);
    for (const char* criterion : {"J1_ms", "J2", "J3"}) {
      EXPECT_TRUE(a[criterion].is_number()) << name << " " << criterion << ": " << a.dump();
    }
  }
  // The compensators' current estimates: each actuator's own, and the substructure's (the
  // smaller of them).
  EXPECT_TRUE(rt["compensation"]["frame"]["delay_s"].is_number()) << rt["compensation"].dump();
  ASSERT_EQ(rt["compensation"]["frame"]["actuators"].size(), 2u) << rt["compensation"].dump();
  for (int k = 0; k < 2; ++k) {
    const nlohmann::json& a = rt["compensation"]["frame"]["actuators"][std::size_t(k)];
    EXPECT_EQ(a["name"], "frame_a" + std::to_string(k + 1));
    EXPECT_TRUE(a["delay_s"].is_number()) << a.dump();
  }
  RecordProperty("misses_at_snapshot", std::to_string(rt["misses"].get<long>()));

  // Hold: asked at step kHoldAt, applied before the next step; nothing committed while held.
  EXPECT_EQ(op.hold_status, 200);
  EXPECT_EQ(steps_when_held, kHoldAt);
  // Stop: asked at step kStopAt, the run ends without another step.
  EXPECT_EQ(op.stop_status, 200);
  EXPECT_EQ(result.status, runner::SessionStatus::kHeld) << result.reason;
  EXPECT_EQ(session.statistics().steps, kStopAt);
  EXPECT_EQ(op.last_step.load(), kStopAt);
  EXPECT_EQ(session.paced_loop()->statistics().ticks, kStopAt);
  const nlohmann::json actions = state.StateJson()["actions"];
  ASSERT_EQ(actions.size(), 3u) << actions.dump();
  EXPECT_EQ(actions[0]["action"], "hold");
  EXPECT_EQ(actions[0]["step"].get<long>(), kHoldAt);
  EXPECT_EQ(actions[1]["action"], "continue");
  EXPECT_EQ(actions[1]["step"].get<long>(), kHoldAt);
  EXPECT_EQ(actions[2]["action"], "stop");
  EXPECT_EQ(actions[2]["step"].get<long>(), kStopAt);
  fs::remove_all(dir);
}

}  // namespace
}  // namespace hybridtest::testing
