// BenchClient against an in-process BenchServer over 127.0.0.1 serving a fake bench: normal
// exchanges and the client's reaction to every fault the server can inject.
#include "hybridtest/transfer/bench_client.h"

#include <gtest/gtest.h>

#include <cmath>

#include "hybridtest/common/error.h"
#include "transfer/bench_fake.h"

namespace hybridtest::transfer {
namespace {

using testing::FakeBench;
using testing::ClientFor;
using testing::ServerThread;

BenchServerOptions WithFault(FaultKind kind, long at) {
  BenchServerOptions o;
  o.faults = {{kind, at}};
  return o;
}

// Runs commands 1..n-1 (positions 0.5 mm apart) that must succeed, then returns the error
// message of command n, which must throw TransferError.
std::string FailureAtCommand(BenchClient& client, int n) {
  for (int i = 1; i < n; ++i) ExecuteOne(client, 0.5 * i);
  try {
    ExecuteOne(client, 0.5 * n);
  } catch (const TransferError& e) {
    return e.what();
  }
  return "<no TransferError>";
}

TEST(BenchClient, ExchangesCommandsAndMeasurements) {
  FakeBench bench;
  ServerThread server(bench, {});
  BenchClient client(ClientFor(server));
  client.Activate();
  ASSERT_TRUE(client.welcome().has_value());
  EXPECT_EQ(client.bench_units().length_name, "mm");
  EXPECT_EQ(client.bench_units().metres_per_length_unit, 1e-3);
  EXPECT_NE(client.Describe().find("fake linear bench"), std::string::npos);
  EXPECT_EQ(client.welcome()->limits.stroke_max, SafetyLimits{}.stroke_max);
  std::vector<double> sent;
  for (int i = 0; i < 20; ++i) {
    const double command = 4.0 * std::sin(0.3 * i);
    sent.push_back(command);
    const Measurement m = ExecuteOne(client, command);
    EXPECT_EQ(m.position, command);  // bit-exact through the wire
    EXPECT_EQ(m.force, FakeBench::kStiffness * command);
    EXPECT_EQ(m.lab_time, i + 1.0);
  }
  client.Heartbeat();
  client.Deactivate();
  EXPECT_FALSE(client.is_connected());
  EXPECT_EQ(bench.commands(), sent);
  EXPECT_GE(bench.holds.load(), 1);  // Deactivate holds first
}

TEST(BenchClient, ExecuteBeforeActivateIsATransferError) {
  BenchClient client(BenchClientOptions{});
  EXPECT_THROW(ExecuteOne(client, 0.0), TransferError);
  EXPECT_NO_THROW(client.Hold());
}

TEST(BenchClient, ConnectionRefusedNamesTheEndpoint) {
  std::uint16_t port = 0;
  {
    FakeBench bench;
    ServerThread server(bench, {});
    port = server.port();
  }  // closed again: nothing listens there now (barring a race with another process)
  BenchClientOptions o;
  o.port = port;
  o.connect_timeout = 2.0;
  BenchClient client(o);
  try {
    client.Activate();
    FAIL() << "expected TransferError";
  } catch (const TransferError& e) {
    EXPECT_NE(std::string(e.what()).find("127.0.0.1:" + std::to_string(port)), std::string::npos);
  }
}

TEST(BenchClient, NanAndSpikeArePassedThroughForTheCallersMonitor) {
  FakeBench bench;
  BenchServerOptions o;
  o.faults = {{FaultKind::kNan, 2}, {FaultKind::kSpike, 3}};
  ServerThread server(bench, o);
  BenchClient client(ClientFor(server));
  client.Activate();
  EXPECT_EQ(ExecuteOne(client, 1.0).force, 5.0);
  EXPECT_TRUE(std::isnan(ExecuteOne(client, 2.0).force));
  EXPECT_EQ(ExecuteOne(client, 3.0).force, 15.0 + kDefaultSpikeForce);  // N: + 1e5 N
  EXPECT_EQ(ExecuteOne(client, 4.0).force, 20.0);
}

TEST(BenchClient, CorruptedFrameIsATransferErrorNamingTheCrc) {
  FakeBench bench;
  ServerThread server(bench, WithFault(FaultKind::kCorrupt, 3));
  BenchClient client(ClientFor(server));
  client.Activate();
  const std::string msg = FailureAtCommand(client, 3);
  EXPECT_NE(msg.find("CRC mismatch"), std::string::npos) << msg;
  EXPECT_FALSE(client.is_connected());
}

TEST(BenchClient, StaleSequenceNumberIsRejected) {
  FakeBench bench;
  ServerThread server(bench, WithFault(FaultKind::kStaleSeq, 2));
  BenchClient client(ClientFor(server));
  client.Activate();
  const std::string msg = FailureAtCommand(client, 2);
  EXPECT_NE(msg.find("stale or duplicate sequence number"), std::string::npos) << msg;
}

TEST(BenchClient, DuplicateMeasurementIsRejected) {
  FakeBench bench;
  ServerThread server(bench, WithFault(FaultKind::kDuplicate, 4));
  BenchClient client(ClientFor(server));
  client.Activate();
  const std::string msg = FailureAtCommand(client, 4);
  EXPECT_NE(msg.find("stale or duplicate sequence number"), std::string::npos) << msg;
}

TEST(BenchClient, SilenceTimesOutAndTheServerHolds) {
  FakeBench bench;
  ServerThread server(bench, WithFault(FaultKind::kSilence, 2));
  BenchClient client(ClientFor(server, 0.3));
  client.Activate();
  const std::string msg = FailureAtCommand(client, 2);
  EXPECT_NE(msg.find("did not answer within 0.3 s"), std::string::npos) << msg;
  EXPECT_NE(msg.find("COMMAND sequence 3"), std::string::npos) << msg;  // HELLO was 1
  EXPECT_EQ(bench.commands().size(), 1u);  // the silent command never moved the bench
  EXPECT_GE(bench.holds.load(), 1);
}

TEST(BenchClient, ClosedConnectionSaysItWasLost) {
  FakeBench bench;
  ServerThread server(bench, WithFault(FaultKind::kClose, 3));
  BenchClient client(ClientFor(server));
  client.Activate();
  const std::string msg = FailureAtCommand(client, 3);
  EXPECT_NE(msg.find("connection to the bench at 127.0.0.1:" + std::to_string(server.port()) +
                     " was lost while waiting for the measurement of COMMAND sequence 4"),
            std::string::npos)
      << msg;
  EXPECT_EQ(bench.commands().size(), 2u);
  // The server survives and serves the next client.
  BenchClient again(ClientFor(server));
  again.Activate();
  EXPECT_EQ(ExecuteOne(again, 1.5).force, 7.5);
}

TEST(BenchClient, WrongTokenIsRefused) {
  FakeBench bench;
  BenchServerOptions o;
  o.token = "right";
  ServerThread server(bench, o);
  BenchClientOptions co = ClientFor(server);
  co.token = "wrong";
  BenchClient client(co);
  try {
    client.Activate();
    FAIL() << "expected TransferError";
  } catch (const TransferError& e) {
    EXPECT_NE(std::string(e.what()).find("ERROR AUTH"), std::string::npos) << e.what();
  }
  co.token = "right";
  BenchClient good(co);
  good.Activate();
  EXPECT_EQ(ExecuteOne(good, 1.0).force, 5.0);
}

}  // namespace
}  // namespace hybridtest::transfer
