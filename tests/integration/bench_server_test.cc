// `hybridtest bench` as a separate process on 127.0.0.1 (port 0), driven by BenchClient:
// normal exchanges with the emulated cantilever, a server killed mid-session, every injected
// fault, tokens, a safety refusal, and the command's argument errors.
#include <gtest/gtest.h>

#include <cmath>

#include "hybridtest/common/error.h"
#include "hybridtest/transfer/bench_client.h"
#include "hybridtest/transfer/safety.h"
#include "hybridtest/transfer/bench_faults.h"
#include "integration/bench_process.h"

namespace hybridtest {
namespace {

using testing::BenchProcess;
using transfer::BenchClient;
using transfer::BenchClientOptions;
using transfer::SafetyStop;
using transfer::kDefaultSpikeForce;

constexpr double kCantileverStiffness = 5.25;  // 3EI/L³ of the default specimen. Unit: [N/mm].

BenchClientOptions ClientFor(const BenchProcess& bench, double reply_timeout = 10.0) {
  BenchClientOptions o;
  o.port = bench.port();
  o.reply_timeout = reply_timeout;
  return o;
}

// Commands 1..n-1 of a 1 mm ramp must succeed; returns the TransferError of command n.
std::string FailureAtCommand(BenchClient& client, int n) {
  for (int i = 1; i < n; ++i) ExecuteOne(client, 1.0 * i);
  try {
    ExecuteOne(client, 1.0 * n);
  } catch (const TransferError& e) {
    return e.what();
  }
  return "<no TransferError>";
}

TEST(BenchProcessTest, ExchangesWithTheEmulatedCantilever) {
  BenchProcess bench({});
  EXPECT_NE(bench.first_line().find("emulated bench"), std::string::npos);
  BenchClient client(ClientFor(bench));
  client.Activate();
  EXPECT_EQ(client.bench_units().length_name, "mm");
  EXPECT_NE(client.Describe().find("cantilever"), std::string::npos);
  double last_lab_time = 0.0;
  for (int i = 1; i <= 8; ++i) {
    const double command = 0.5 * i;  // mm
    const transfer::Measurement m = ExecuteOne(client, command);
    EXPECT_NEAR(m.position, command, 0.01);                          // settled within 10 µm
    EXPECT_NEAR(m.force, kCantileverStiffness * m.position, 0.1);  // 3EI/L³, averaged noise
    EXPECT_GT(m.lab_time, last_lab_time);
    last_lab_time = m.lab_time;
  }
  client.Deactivate();
  bench.Signal(SIGTERM);
  EXPECT_EQ(bench.WaitExit(10.0), 0);
}

TEST(BenchProcessTest, ServerKilledMidSessionIsALostConnection) {
  BenchProcess bench({});
  BenchClient client(ClientFor(bench, 5.0));
  client.Activate();
  ExecuteOne(client, 1.0);
  bench.Signal(SIGKILL);
  ASSERT_EQ(bench.WaitExit(10.0), 128 + SIGKILL);
  try {
    ExecuteOne(client, 2.0);
    FAIL() << "expected TransferError";
  } catch (const TransferError& e) {
    const std::string msg = e.what();
    EXPECT_NE(msg.find("connection to the bench at 127.0.0.1:" + std::to_string(bench.port()) +
                       " was lost"),
              std::string::npos)
        << msg;
    EXPECT_NE(msg.find("COMMAND sequence 3"), std::string::npos) << msg;
  }
}

TEST(BenchProcessTest, NanForceIsCaughtByTheCallersMonitor) {
  BenchProcess bench({"--inject", "nan@2"});
  BenchClient client(ClientFor(bench));
  client.Activate();
  transfer::SafetyMonitor monitor(transfer::SafetyLimits{});
  const transfer::Measurement ok = ExecuteOne(client, 1.0);
  monitor.CheckMeasurement(1e-3, ok.position * 1e-3, ok.force, 0, 0);
  const transfer::Measurement bad = ExecuteOne(client, 2.0);
  EXPECT_TRUE(std::isnan(bad.force));
  try {
    monitor.CheckMeasurement(2e-3, bad.position * 1e-3, bad.force, 1, 0);
    FAIL() << "expected SafetyStop";
  } catch (const SafetyStop& e) {
    EXPECT_EQ(e.limit(), "force_finite");
  }
}

TEST(BenchProcessTest, ForceSpikeAddsTheSpikeForceAndTripsTheHardLimit) {
  BenchProcess bench({"--inject", "spike@5"});
  BenchClient client(ClientFor(bench));
  client.Activate();
  transfer::SafetyMonitor monitor(transfer::SafetyLimits{});
  for (int i = 1; i <= 4; ++i) {
    const transfer::Measurement m = ExecuteOne(client, 4.0 * i);
    monitor.CheckMeasurement(4e-3 * i, m.position * 1e-3, m.force, i, 0);
  }
  const transfer::Measurement spike = ExecuteOne(client, 20.0);
  // One spike semantics (bench_faults.h): + 1e5 N, in the bench's force unit (N here).
  EXPECT_NEAR(spike.force - kDefaultSpikeForce, kCantileverStiffness * spike.position, 0.1);
  EXPECT_THROW(monitor.CheckMeasurement(20e-3, spike.position * 1e-3, spike.force, 5, 0),
               SafetyStop);
}

TEST(BenchProcessTest, CorruptedFrameIsATransferError) {
  BenchProcess bench({"--inject", "corrupt@2"});
  BenchClient client(ClientFor(bench));
  client.Activate();
  const std::string msg = FailureAtCommand(client, 2);
  EXPECT_NE(msg.find("CRC mismatch"), std::string::npos) << msg;
}

TEST(BenchProcessTest, StaleAndDuplicateSequenceNumbersAreRejected) {
  for (const char* fault : {"stale_seq@3", "duplicate@3"}) {
    BenchProcess bench({"--inject", fault});
    BenchClient client(ClientFor(bench));
    client.Activate();
    const std::string msg = FailureAtCommand(client, 3);
    EXPECT_NE(msg.find("stale or duplicate sequence number"), std::string::npos)
        << fault << ": " << msg;
  }
}

TEST(BenchProcessTest, SilenceTimesOut) {
  BenchProcess bench({"--inject", "silence@2"});
  BenchClient client(ClientFor(bench, 1.0));
  client.Activate();
  const std::string msg = FailureAtCommand(client, 2);
  EXPECT_NE(msg.find("did not answer within 1 s"), std::string::npos) << msg;
}

TEST(BenchProcessTest, WrongTokenIsRefusedAndTheEnvironmentTokenWorks) {
  BenchProcess bench({}, {"HYBRIDTEST_BENCH_TOKEN=s3cret"});
  EXPECT_NE(bench.first_line().find("token required"), std::string::npos);
  BenchClientOptions o = ClientFor(bench);
  o.token = "guess";
  BenchClient wrong(o);
  try {
    wrong.Activate();
    FAIL() << "expected TransferError";
  } catch (const TransferError& e) {
    EXPECT_NE(std::string(e.what()).find("ERROR AUTH"), std::string::npos) << e.what();
  }
  o.token = "s3cret";
  BenchClient right(o);
  right.Activate();
  EXPECT_NEAR(ExecuteOne(right, 1.0).position, 1.0, 0.01);
}

TEST(BenchProcessTest, CommandBeyondStrokeIsRefusedAndTheBenchHolds) {
  BenchProcess bench({});
  BenchClient client(ClientFor(bench));
  client.Activate();
  const transfer::Measurement before = ExecuteOne(client, 3.0);
  try {
    ExecuteOne(client, 151.0);  // mm; the stroke ends at 150 mm
    FAIL() << "expected SafetyStop";
  } catch (const SafetyStop& e) {
    EXPECT_EQ(e.limit(), "stroke_max");
    EXPECT_NEAR(e.value(), 0.151, 1e-12);
    EXPECT_NEAR(e.limit_value(), 0.150, 1e-12);
  }
  // Held: the session refuses every further command, even a harmless one.
  EXPECT_THROW(ExecuteOne(client, 3.0), SafetyStop);
  client.Hold();
  client.Deactivate();
  // A new session finds the actuator where it was held (it never moved toward 151 mm).
  BenchClient next(ClientFor(bench));
  next.Activate();
  const transfer::Measurement after = ExecuteOne(next, 3.0);
  EXPECT_NEAR(after.position, before.position, 0.01);
  EXPECT_NEAR(after.force, before.force, 0.1);
}

TEST(BenchProcessTest, ArgumentErrorsAreClear) {
  const std::string exe = HYBRIDTEST_BINARY;
  auto [status, out] = testing::RunCommand(exe + " bench --listen 0.0.0.0:0");
  EXPECT_EQ(status, 2);
  EXPECT_NE(out.find("without a token"), std::string::npos) << out;
  std::tie(status, out) = testing::RunCommand(exe + " bench --listen localhost");
  EXPECT_EQ(status, 2);
  EXPECT_NE(out.find("expected HOST:PORT"), std::string::npos) << out;
  std::tie(status, out) = testing::RunCommand(exe + " bench --inject boom@1 --listen 127.0.0.1:0");
  EXPECT_EQ(status, 2);
  EXPECT_NE(out.find("unknown fault kind 'boom'"), std::string::npos) << out;
  BenchProcess first({});
  std::tie(status, out) =
      testing::RunCommand(exe + " bench --listen 127.0.0.1:" + std::to_string(first.port()));
  EXPECT_EQ(status, 4);
  EXPECT_NE(out.find("cannot listen on 127.0.0.1:" + std::to_string(first.port())),
            std::string::npos)
      << out;
}

}  // namespace
}  // namespace hybridtest
