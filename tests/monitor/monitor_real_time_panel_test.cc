// The monitor's real-time panel (issue 38): the lateness and compute percentiles of the
// histogram against the sorted samples; on a paced run of examples/real-time/storey-ats.yaml
// (1 s of it, virtual clock), /api/state's `realtime` mid-run is the paced loop's (ticks,
// misses, J2 and J3 equal to those computed from the journal's rows so far, J1 the running
// estimate over the last second, per actuator too, the ATS compensator's current delay), and at
// the end it is what the run records (its
// statistics.real_time: J1 included).
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <random>
#include <thread>
#include <vector>

#include "hybridtest/common/tracking.h"
#include "hybridtest/io/run_spec_yaml.h"
#include "hybridtest/monitor/monitor_observer.h"
#include "hybridtest/monitor/real_time_panel.h"
#include "hybridtest/runner/paced_loop.h"
#include "monitor/example_config.h"

namespace hybridtest::testing {
namespace {

TEST(DurationHistogram, PercentilesAreWithinOneBinAboveTheSortedSamples) {
  std::mt19937_64 gen(38);
  std::lognormal_distribution<double> dist(std::log(20e-6), 1.0);
  std::vector<double> v(5000);
  monitor::DurationHistogram h;
  for (double& x : v) {
    x = dist(gen);
    h.Add(x);
  }
  std::sort(v.begin(), v.end());
  for (double p : {0.5, 0.9, 0.99}) {
    const double exact = v[std::size_t(std::ceil(p * double(v.size()))) - 1];
    EXPECT_GE(h.Percentile(p), exact) << p;
    EXPECT_LE(h.Percentile(p), exact * 1.05 + 1e-12) << p;
  }
  EXPECT_DOUBLE_EQ(h.max(), v.back());
  EXPECT_EQ(h.count(), 5000);
  EXPECT_EQ(monitor::DurationHistogram().Percentile(0.5), 0.0);
}

// Takes /api/state once step `at` is in the monitor's state (the collector drains it), with
// what the paced loop and the compensator hold at that moment, on the stepping thread.
class Snapshot final : public runner::SessionObserver {
 public:
  Snapshot(monitor::MonitorState& state, const runner::Session& session, long at)
      : state_(state), session_(session), at_(at) {}
  void OnCommit(const runner::CommitEvent& e) override {
    if (e.kind != runner::RowKind::kCommitted) return;
    if (e.step >= 1 && e.step <= at_) {
      // The row's actuator: command and position after t, x (2 + 2 + 0) and r (1).
      const std::size_t c = 1 + e.x.size() + e.r.size();
      command.push_back(e.row[c]);
      position.push_back(e.row[c + 1]);
    }
    if (e.step != at_) return;
    // A slot without a transfer system leaves NaN, which no recorded delay equals.
    const transfer::TransferSystem* transfer = session_.substructures()[0]->transfer_system();
    delay = transfer != nullptr ? transfer->compensated_delay()
                                : std::numeric_limits<double>::quiet_NaN();
    delays.clear();
    for (int k = 0; transfer != nullptr && k < transfer->num_actuators(); ++k) {
      delays.push_back(transfer->actuator_compensated_delay(k));
    }
    for (int i = 0; i < 2000 && state_.frames() <= at_; ++i) {
      std::this_thread::sleep_for(std::chrono::milliseconds(5));
    }
    json = state_.StateJson();
  }
  bool real_time_safe() const override { return true; }  // a test: it may wait for the drain

  std::vector<double> command, position;
  double delay = 0.0;
  std::vector<double> delays;  // each actuator's compensator's estimate [s]
  nlohmann::json json;

 private:
  monitor::MonitorState& state_;
  const runner::Session& session_;
  long at_;
};

// A paced run of `config` on the virtual clock without files, watched by the monitor, with
// /api/state taken at step `at`.
io::RunSpec VirtualSpec(const fs::path& config) {
  io::RunSpec spec = io::LoadRunSpec(config.string());
  spec.output.files = false;
  spec.real_time.clock = "virtual";
  return spec;
}
struct MonitoredRun {
  MonitoredRun(const fs::path& config, long at)
      : session(VirtualSpec(config)), observer(state), snapshot(state, session, at) {
    session.AddObserver(observer);
    session.AddObserver(snapshot);
  }
  runner::Session session;
  monitor::MonitorState state{100000};
  monitor::MonitorObserver observer;
  Snapshot snapshot;
};

TEST(MonitorRealTimePanel, ThePanelIsThePacedLoopsLiveAndTheRecordAtTheEnd) {
  const fs::path dir = ResumeTestDir("monitor_real_time_panel");
  const fs::path config = WriteExampleConfig(
      dir, "real-time", "storey-ats.yaml",
      {{"duration: 10.0", "duration: 1.0"}, {"lock_memory: true", "lock_memory: false"}},
      {"storey.model.yaml"});
  MonitoredRun run(config, 600);
  runner::Session& session = run.session;
  monitor::MonitorState& state = run.state;
  Snapshot& snapshot = run.snapshot;
  ASSERT_NE(session.paced_loop(), nullptr);
  ASSERT_EQ(session.Run().status, runner::SessionStatus::kFinished);

  // Mid-run: the paced loop's counts, and J2, J3 of the rows so far.
  const nlohmann::json& live = snapshot.json["realtime"];
  ASSERT_TRUE(live["available"].get<bool>()) << snapshot.json.dump();
  EXPECT_EQ(live["source"], "live");
  EXPECT_EQ(live["clock"], "virtual");
  EXPECT_EQ(live["ticks"], 600);
  EXPECT_EQ(live["misses"], 0);  // the virtual clock is never late
  EXPECT_EQ(live["misses_in_a_row"], 0);
  EXPECT_EQ(live["hold_after_misses"], 10);
  EXPECT_DOUBLE_EQ(live["late_s"]["max"].get<double>(), 0.0);
  EXPECT_GT(live["compute_s"]["max"].get<double>(), 0.0);
  const auto n = static_cast<double>(snapshot.command.size());
  ASSERT_EQ(snapshot.command.size(), 600u);
  double sc = 0, scc = 0, se = 0, see = 0, emax = 0, cmax = 0;
  for (std::size_t i = 0; i < snapshot.command.size(); ++i) {
    const double c = snapshot.command[i], e = snapshot.position[i] - c;
    sc += c, scc += c * c, se += e, see += e * e;
    emax = std::max(emax, std::abs(e));
    cmax = std::max(cmax, std::abs(c));
  }
  const double j2 = 100.0 * std::sqrt(see / n - (se / n) * (se / n)) /
                    std::sqrt(scc / n - (sc / n) * (sc / n));
  EXPECT_GT(j2, 0.0);
  EXPECT_NEAR(live["J2"].get<double>(), j2, 1e-9 * j2);
  EXPECT_NEAR(live["J3"].get<double>(), 100.0 * emax / cmax, 1e-9);
  // J1 live: the running estimate over the last second, recomputed for actuator r1 at tick 576
  // (every 64 ticks, r1 and its slot in turn), from the 576 samples then.
  const double j1 = TrackingDelayMs(std::span(snapshot.position).first(576),
                                    std::span(snapshot.command).first(576), 0.0009765625, 0.2);
  ASSERT_TRUE(live["J1_ms"].is_number()) << live.dump();
  EXPECT_DOUBLE_EQ(live["J1_ms"].get<double>(), j1);
  // Per actuator: the one actuator's J1–J3, named as its journal channels.
  ASSERT_EQ(live["actuators"].size(), 1u) << live.dump();
  EXPECT_EQ(live["actuators"][0]["name"], "r1");
  EXPECT_DOUBLE_EQ(live["actuators"][0]["J1_ms"].get<double>(), j1);
  EXPECT_NEAR(live["actuators"][0]["J2"].get<double>(), j2, 1e-9 * j2);
  EXPECT_DOUBLE_EQ(live["compensation"]["r1"]["delay_s"].get<double>(), snapshot.delay);

  // At the end: the run's own record.
  const nlohmann::json end = state.StateJson()["realtime"];
  const nlohmann::json record = session.paced_loop()->ToJson();
  EXPECT_EQ(end["source"], "recorded");
  EXPECT_EQ(end["ticks"], 1024);
  EXPECT_EQ(end["ticks"], record["ticks"]);
  EXPECT_EQ(end["misses"], record["misses"]);
  EXPECT_DOUBLE_EQ(end["J1_ms"].get<double>(), record["J1_ms"].get<double>());
  EXPECT_DOUBLE_EQ(end["J3"].get<double>(), record["J3"].get<double>());
  EXPECT_EQ(end["compensation"]["r1"]["method"], "ats");
  fs::remove_all(dir);
}

// Two actuators, each with its own ATS compensator (issue 46): /api/state's compensation entry
// carries each actuator's own estimate, named as its journal channels, and the substructure's
// delay_s is the smaller. (Before, it carried only the substructure's smaller estimate.)
TEST(MonitorRealTimePanel, CompensationIsLivePerActuator) {
  const fs::path dir = ResumeTestDir("monitor_real_time_panel_two");
  const fs::path config = WriteExampleConfig(
      dir, "06_blade_two_actuators", "real-time.yaml",
      {{"duration: 10.0", "duration: 1.5"},
       {"delay: 0\\.0 +# \\[s\\] pure delay", "delay: [0.0, 0.001]  # [s] pure delay"}},
      {"blade_tip.yaml"});
  MonitoredRun run(config, 1400);
  ASSERT_EQ(run.session.Run().status, runner::SessionStatus::kFinished);
  Snapshot& snapshot = run.snapshot;

  nlohmann::json c = snapshot.json["realtime"]["compensation"]["blade1"];
  ASSERT_EQ(snapshot.delays.size(), 2u);
  ASSERT_TRUE(c["actuators"].is_array()) << c.dump();
  ASSERT_EQ(c["actuators"].size(), 2u) << c.dump();
  for (std::size_t k = 0; k < 2; ++k) {
    EXPECT_EQ(c["actuators"][k]["name"], "blade1_a" + std::to_string(k + 1));
    ASSERT_TRUE(c["actuators"][k]["delay_s"].is_number()) << c.dump();
    EXPECT_DOUBLE_EQ(c["actuators"][k]["delay_s"].get<double>(), snapshot.delays[k]);
  }
  // Each its own: the actuator with 1 ms more plant delay has another estimate.
  EXPECT_NE(snapshot.delays[0], snapshot.delays[1]);
  EXPECT_DOUBLE_EQ(c["delay_s"].get<double>(), std::min(snapshot.delays[0], snapshot.delays[1]));
  fs::remove_all(dir);
}

// The monitor takes each compensator's delay from the pacer's sample (RealTimeSample::
// compensated_delay_s), never from the transfer system: fed a row whose sample carries a delay
// the compensator never estimated, /api/state's compensation shows the sample's. (Before, the
// observer read the compensator itself on the stepping thread.)
TEST(MonitorRealTimePanel, CompensationComesFromThePacersSample) {
  const fs::path dir = ResumeTestDir("monitor_real_time_panel_sample");
  const fs::path config = WriteExampleConfig(
      dir, "real-time", "storey-ats.yaml", {{"lock_memory: true", "lock_memory: false"}},
      {"storey.model.yaml"});
  runner::Session session(VirtualSpec(config));  // built, never run: nothing moves
  monitor::MonitorState state(100);
  monitor::MonitorObserver observer(state);
  observer.OnStart({session.spec(), session.slot_map(), session.substructures(), true, nullptr,
                    "virtual"});
  const transfer::TransferSystem* ats = session.substructures()[0]->transfer_system();
  ASSERT_NE(ats, nullptr);
  const double delay = 0.0123456;  // [s]
  ASSERT_NE(ats->actuator_compensated_delay(0), delay);
  const std::vector<double> delays{delay};
  runner::RealTimeSample sample;
  sample.ticks = 1;
  sample.compensated_delay_s = delays;
  runner::CommitEvent row;
  row.step = 1;
  row.real_time = &sample;
  observer.OnCommit(row);
  for (int i = 0; i < 2000 && state.frames() < 1; ++i) {
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
  const nlohmann::json c = state.StateJson()["realtime"]["compensation"]["r1"];
  ASSERT_TRUE(c["actuators"].is_array()) << c.dump();
  ASSERT_EQ(c["actuators"].size(), 1u) << c.dump();
  EXPECT_EQ(c["actuators"][0]["name"], "r1");
  EXPECT_DOUBLE_EQ(c["actuators"][0]["delay_s"].get<double>(), delay) << c.dump();
  EXPECT_DOUBLE_EQ(c["delay_s"].get<double>(), delay) << c.dump();
  runner::StopEvent stop;
  stop.statistics = nlohmann::json::object();
  observer.OnStop(stop);
  fs::remove_all(dir);
}

}  // namespace
}  // namespace hybridtest::testing
