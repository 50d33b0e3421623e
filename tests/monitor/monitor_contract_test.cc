// Issue 33's contract for the live monitor, with the real binary on loopback:
//  - the operator's Hold, Continue and Stop (right token, from 127.0.0.1, after 5 wrong tokens
//    of its own) are served during a wrong-token flood from rotating 127.0.0.x addresses;
//  - with 8 viewers that drip one header line every 2 s and 30 that poll as the page does, an
//    authenticated Stop ends a lab-time run within 1 s and the process exits within 2 s of
//    the run's end;
//  - the real-time storey (examples/real-time/storey-ats.yaml, wall clock) with 30 polling
//    viewers completes; its deadline misses are recorded (test output and XML properties),
//    never asserted (they depend on the machine's load).
#include <atomic>
#include <fstream>
#include <iostream>

#include "monitor/monitor_process.h"
#include "monitor/polling_viewers.h"
#include "monitor/raw_http.h"
#include "support/listening_process.h"

namespace hybridtest::testing {
namespace {

const std::string kToken = "monitor-contract-token-0123456789";
using SteadyClock = std::chrono::steady_clock;

double SecondsSince(SteadyClock::time_point t0) {
  return std::chrono::duration<double>(SteadyClock::now() - t0).count();
}

class MonitorContract : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir_ = ResumeTestDir("monitor_contract");
    test_support::WriteText(dir_ / "token", kToken + "\n");
    // The ideal emulated rotor for 600 s of simulated time: long enough to be stopped.
    test_support::WriteText(
        dir_ / "long.yaml",
        "model: {name: rotor, blades: 3}\nintegrator: {tableau: heun, dt: 0.001}\n"
        "duration: 600.0\nsubstructures:\n  r1:\n    type: physical\n    transfer:\n"
        "      type: emulated\n      config: " + kSource + "/examples/rotor/bench-ideal.yaml\n"
        "    setup: {p0: 0.020}\n    safety: {stroke_min: -0.15, stroke_max: 0.15, "
        "max_increment: 0.005, force_soft: 8000, force_hard: 10000, timeout: 5}\n");
  }
  static void TearDownTestSuite() { fs::remove_all(dir_); }
  static std::vector<std::string> LongRun(const std::string& name) {
    return {"run", (dir_ / "long.yaml").string(), "--out", (dir_ / (name + ".csv")).string(),
            "--quiet", "--monitor", "127.0.0.1:0", "--token-file", (dir_ / "token").string()};
  }
  static inline fs::path dir_;
};

TEST_F(MonitorContract, TheOperatorIsServedDuringAWrongTokenFloodFromRotatingAddresses) {
  MonitoredRun run(LongRun("flood"), dir_ / "flood.log");
  ASSERT_NE(run.port(), 0) << run.child().output();
  ASSERT_TRUE(run.WaitState([](const auto& s) { return s["step"].template get<long>() > 100; }));
  const int port = run.port();
  // The operator's own address has sent 5 wrong tokens.
  for (int i = 0; i < 5; ++i) RequestFrom("127.0.0.1", port, "POST", "/api/hold", "typo");
  std::atomic<bool> done{false};
  std::atomic<long> flood{0};
  std::thread attacker([&] {
    for (int i = 0; !done.load() && i < 50000; ++i) {
      RequestFrom("127.0.0." + std::to_string(2 + i % 250), port, "POST",
                  i % 2 == 0 ? "/api/stop" : "/api/hold", "guess" + std::to_string(i), 2.0);
      ++flood;
    }
  });
  std::this_thread::sleep_for(std::chrono::milliseconds(500));
  EXPECT_EQ(RequestFrom("127.0.0.1", port, "POST", "/api/hold", kToken), 200);
  ASSERT_TRUE(run.WaitState([](const auto& s) { return s["status"] == "holding"; }));
  EXPECT_EQ(RequestFrom("127.0.0.1", port, "POST", "/api/continue", kToken), 200);
  std::this_thread::sleep_for(std::chrono::milliseconds(300));
  EXPECT_EQ(RequestFrom("127.0.0.1", port, "POST", "/api/stop", kToken), 200);
  const int status = run.child().WaitExit(30.0);
  done = true;
  attacker.join();
  std::cout << "wrong tokens sent during the test: " << flood.load() << "\n";
  RecordProperty("wrong_tokens", std::to_string(flood.load()));
  ASSERT_EQ(status, 130) << run.child().output();
  EXPECT_GT(flood.load(), 10);
  const nlohmann::json actions = Sidecar(dir_ / "flood.csv")["operator_actions"];
  ASSERT_EQ(actions.size(), 3u) << actions.dump();
  EXPECT_EQ(actions[0]["action"], "hold");
  EXPECT_EQ(actions[1]["action"], "continue");
  EXPECT_EQ(actions[2]["action"], "stop");
}

TEST_F(MonitorContract, DrippingAndPollingViewersDelayNeitherStopNorTheExit) {
  MonitoredRun run(LongRun("viewers"), dir_ / "viewers.log");
  ASSERT_NE(run.port(), 0) << run.child().output();
  ASSERT_TRUE(run.WaitState([](const auto& s) { return s["step"].template get<long>() > 100; }));
  const int port = run.port();
  Viewers viewers(port, /*pollers=*/30, /*drippers=*/8);
  // Long enough for every dripper to have sent a header line or two.
  std::this_thread::sleep_for(std::chrono::milliseconds(4500));
  const auto t0 = SteadyClock::now();
  ASSERT_EQ(RequestFrom("127.0.0.1", port, "POST", "/api/stop", kToken, 5.0), 200);
  const double answered = SecondsSince(t0);
  // The run's end: the state says "stopped" (or the process has already gone).
  double ended = -1;
  while (SecondsSince(t0) < 10.0) {
    const int fd = ConnectFrom("127.0.0.1", port);
    if (fd < 0) {
      ended = SecondsSince(t0);
      break;
    }
    SendAll(fd, "GET /api/state HTTP/1.1\r\nConnection: close\r\n\r\n");
    const std::string answer = ReadUntilClosed(fd, 2.0);
    ::close(fd);
    if (answer.find("\"status\":\"stopped\"") != std::string::npos || answer.empty()) {
      ended = SecondsSince(t0);
      break;
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  const auto t_end = SteadyClock::now();
  const int status = run.child().WaitExit(10.0);
  const double exited = SecondsSince(t_end);
  std::cout << "stop answered after " << answered << " s, run ended after " << ended
            << " s, process exited " << exited << " s after the end; viewer answers "
            << viewers.answered() << ", drippers cut off " << viewers.drips_cut() << "\n";
  RecordProperty("stop_answered_s", std::to_string(answered));
  RecordProperty("run_ended_s", std::to_string(ended));
  RecordProperty("exit_after_end_s", std::to_string(exited));
  viewers.Join();
  ASSERT_EQ(status, 130) << run.child().output();
  EXPECT_GE(ended, 0.0);
  EXPECT_LE(ended, 1.0) << "the Stop did not end the run within 1 s";
  EXPECT_LE(exited, 2.0) << "the process outlived the run's end by more than 2 s";
  EXPECT_GT(viewers.answered(), 30) << "the polling viewers were not served";
  EXPECT_GT(viewers.drips_cut(), 0) << "no dripping viewer was cut off";
}

TEST_F(MonitorContract, TheRealTimeStoreyWithThirtyViewersCompletes) {
  // examples/real-time/storey-ats.yaml, except that it never holds on missed deadlines (this
  // machine's load is not the test's subject): the misses are recorded, not asserted.
  std::string config = test_support::ReadText(kSource + "/examples/real-time/storey-ats.yaml");
  auto replace = [&](const std::string& from, const std::string& to) {
    const std::size_t at = config.find(from);
    ASSERT_NE(at, std::string::npos) << from;
    config.replace(at, from.size(), to);
  };
  replace("file: storey.model.yaml", "file: " + kSource + "/examples/real-time/storey.model.yaml");
  replace("hold_after_misses: 10", "hold_after_misses: 0");
  // The force gate keeps the example's limits: its stiffness estimate is a line fitted
  // through the last exchanges (transfer/safety.h), which late ticks under load no longer
  // throw to 50 × the specimen's stiffness (a forecast 85 kN against 40 kN stopped this run
  // at a load average of 8 while the gate took the secant of the last two measurements).
  test_support::WriteText(dir_ / "storey.yaml", config);
  const fs::path csv = dir_ / "storey.csv";
  MonitoredRun run({"run", (dir_ / "storey.yaml").string(), "--clock", "wall", "--out",
                    csv.string(), "--quiet", "--monitor", "127.0.0.1:0", "--token-file",
                    (dir_ / "token").string()},
                   dir_ / "storey.log");
  ASSERT_NE(run.port(), 0) << run.child().output();
  Viewers viewers(run.port(), /*pollers=*/30, /*drippers=*/0);
  const int status = run.child().WaitExit(120.0);
  viewers.Join();
  ASSERT_EQ(status, 0) << run.child().output();
  const nlohmann::json rt = Sidecar(csv)["statistics"]["real_time"];
  std::cout << "real-time storey with 30 viewers: " << rt.dump() << "\n";
  RecordProperty("misses", std::to_string(rt.value("misses", -1L)));
  EXPECT_EQ(ReadLines(csv).size(), 10242u);  // 10 s at 1024 Hz, and the header and t = 0
  EXPECT_GT(viewers.answered(), 30);
}

}  // namespace
}  // namespace hybridtest::testing
