// BenchServer policy over 127.0.0.1 with a fake bench: bind policy, safety refusal and latch,
// holds on timeouts / protocol errors / disconnects, busy clients, stop.
#include "hybridtest/transfer/bench_server.h"

#include <array>
#include <gtest/gtest.h>

#include <chrono>
#include <thread>

#include "hybridtest/common/error.h"
#include "hybridtest/transfer/bench_client.h"
#include "hybridtest/transfer/protocol.h"
#include "transfer/bench_fake.h"
#include "support/eventually.h"

namespace hybridtest::transfer {
namespace {

using testing::FakeBench;
using testing::ClientFor;
using testing::ServerThread;

using test_support::Eventually;

TEST(BenchServer, RefusesNonLoopbackWithoutToken) {
  FakeBench bench;
  BenchServerOptions o;
  o.host = "0.0.0.0";
  o.port = 0;
  try {
    BenchServer server(bench, o);
    FAIL() << "expected ConfigError";
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("without a token"), std::string::npos);
  }
}

TEST(BenchServer, PortInUseIsATransferError) {
  FakeBench bench;
  ServerThread first(bench, {});
  BenchServerOptions o;
  o.port = first.port();
  EXPECT_THROW(BenchServer(bench, o), TransferError);
}

TEST(BenchServer, CommandBeyondStrokeIsRefusedAsSafetyStopAndLatches) {
  FakeBench bench;
  BenchServerOptions o;
  o.start_position = 0.0;
  ServerThread server(bench, o);
  BenchClient client(ClientFor(server));
  client.Activate();
  ExecuteOne(client, 3.0);
  const int holds_before = bench.holds.load();
  try {
    ExecuteOne(client, 3.0 + 6.0);  // 6 mm jump > max_increment 5 mm
    FAIL() << "expected SafetyStop";
  } catch (const SafetyStop& e) {
    EXPECT_EQ(e.limit(), "max_increment");
    EXPECT_NEAR(e.value(), 6e-3, 1e-12);  // SI
    EXPECT_EQ(e.limit_value(), SafetyLimits{}.max_increment);
  }
  EXPECT_GT(bench.holds.load(), holds_before);
  EXPECT_EQ(bench.commands(), std::vector<double>{3.0});  // the refused command never moved it
  // Latched: even a harmless command is refused now; HOLD still works.
  EXPECT_THROW(ExecuteOne(client, 3.0), SafetyStop);
  EXPECT_TRUE(client.is_connected());
  client.Hold();
  EXPECT_TRUE(client.is_connected());
  client.Deactivate();
  // A new session may move again, from the last safe command.
  BenchClient next(ClientFor(server));
  next.Activate();
  EXPECT_EQ(ExecuteOne(next, 4.0).position, 4.0);
  EXPECT_EQ(bench.commands(), (std::vector<double>{3.0, 4.0}));
}

TEST(BenchServer, StrokeLimitNamesTheLimit) {
  FakeBench bench;
  BenchServerOptions o;
  o.limits.max_increment = 1.0;  // let the stroke check be the one that fires
  ServerThread server(bench, o);
  BenchClient client(ClientFor(server));
  client.Activate();
  try {
    ExecuteOne(client, 151.0);  // mm; stroke_max = 150 mm
    FAIL() << "expected SafetyStop";
  } catch (const SafetyStop& e) {
    EXPECT_EQ(e.limit(), "stroke_max");
    EXPECT_NE(std::string(e.what()).find("refused"), std::string::npos);
  }
  EXPECT_TRUE(bench.commands().empty());
}

TEST(BenchServer, MeasuredForceBeyondHardLimitStopsAndHolds) {
  FakeBench bench;
  bench.extra_force = 2e4;  // N, beyond force_hard = 10 kN
  ServerThread server(bench, {});
  BenchClient client(ClientFor(server));
  client.Activate();
  try {
    ExecuteOne(client, 1.0);
    FAIL() << "expected SafetyStop";
  } catch (const SafetyStop& e) {
    EXPECT_EQ(e.limit(), "force_hard");
  }
  EXPECT_GE(bench.holds.load(), 1);
}

TEST(BenchServer, SilentClientIsDroppedAndTheBenchHolds) {
  FakeBench bench;
  BenchServerOptions o;
  o.heartbeat_timeout = 0.3;
  ServerThread server(bench, o);
  BenchClient client(ClientFor(server));
  client.Activate();
  ExecuteOne(client, 1.0);
  const int holds = bench.holds.load();
  ASSERT_TRUE(Eventually([&] { return bench.holds.load() > holds; }));
  EXPECT_THROW(ExecuteOne(client, 1.5), TransferError);
  EXPECT_EQ(bench.commands(), std::vector<double>{1.0});  // held, never moved again
}

TEST(BenchServer, HeartbeatsKeepTheSessionAlive) {
  FakeBench bench;
  BenchServerOptions o;
  o.heartbeat_timeout = 1.0;
  ServerThread server(bench, o);
  BenchClient client(ClientFor(server));
  client.Activate();
  for (int i = 0; i < 15; ++i) {  // 3 s of idling, a heartbeat every 0.2 s
    client.Heartbeat();
    std::this_thread::sleep_for(std::chrono::milliseconds(200));
  }
  EXPECT_EQ(ExecuteOne(client, 2.0).force, 10.0);
}

TEST(BenchServer, GarbageBeforeHelloIsRefusedWithoutTouchingTheBenchAndServesTheNext) {
  FakeBench bench;
  ServerThread server(bench, {});
  {
    Socket raw = ConnectTcp("127.0.0.1", server.port(), 2.0);
    const std::vector<std::uint8_t> junk(40, 0x55);
    ASSERT_TRUE(SendAll(raw.fd(), junk, 2.0));
    Frame reply;
    ASSERT_EQ(ReadFrame(raw.fd(), 5.0, reply), ReadStatus::kFrame);
    const ErrorMessage error = DecodeError(reply);
    EXPECT_EQ(error.code, ErrorCode::kProtocol);
    EXPECT_NE(error.text.find("bad frame magic"), std::string::npos) << error.text;
  }
  EXPECT_EQ(bench.holds.load(), 0);  // an unauthenticated peer never reaches the bench
  BenchClient client(ClientFor(server));
  client.Activate();
  EXPECT_EQ(ExecuteOne(client, 1.0).force, 5.0);
}

TEST(BenchServer, OversizeLengthIsRejectedBeforeThePayloadIsRead) {
  FakeBench bench;
  ServerThread server(bench, {});
  Socket raw = ConnectTcp("127.0.0.1", server.port(), 2.0);
  auto bytes = EncodeFrame(EncodeHello(1, HelloMessage{}));
  bytes[14] = 0x10;  // payload_length += 1 MiB; the payload itself is never sent
  bytes.resize(kFrameHeaderSize);
  ASSERT_TRUE(SendAll(raw.fd(), bytes, 2.0));
  Frame reply;
  ASSERT_EQ(ReadFrame(raw.fd(), 5.0, reply), ReadStatus::kFrame);
  const ErrorMessage error = DecodeError(reply);
  EXPECT_EQ(error.code, ErrorCode::kProtocol);
  EXPECT_NE(error.text.find("oversize payload length"), std::string::npos) << error.text;
}

TEST(BenchServer, CommandBeforeHelloIsAProtocolError) {
  FakeBench bench;
  ServerThread server(bench, {});
  Socket raw = ConnectTcp("127.0.0.1", server.port(), 2.0);
  ASSERT_TRUE(SendAll(raw.fd(), EncodeFrame(EncodeCommands(1, std::array<double, 1>{1.0})), 2.0));
  Frame reply;
  ASSERT_EQ(ReadFrame(raw.fd(), 5.0, reply), ReadStatus::kFrame);
  EXPECT_EQ(DecodeError(reply).code, ErrorCode::kProtocol);
  EXPECT_TRUE(bench.commands().empty());
}

TEST(BenchServer, SecondClientIsToldTheBenchIsBusy) {
  FakeBench bench;
  ServerThread server(bench, {});
  BenchClient first(ClientFor(server));
  first.Activate();
  EXPECT_EQ(ExecuteOne(first, 1.0).force, 5.0);  // the first client commands
  BenchClient second(ClientFor(server));
  second.Activate();  // a second session opens: it may read
  try {
    ExecuteOne(second, 3.0);
    FAIL() << "expected TransferError";
  } catch (const TransferError& e) {
    EXPECT_NE(std::string(e.what()).find("BUSY"), std::string::npos) << e.what();
  }
  EXPECT_EQ(ExecuteOne(first, 2.0).force, 10.0);
  EXPECT_EQ(bench.commands(), (std::vector<double>{1.0, 2.0}));
}

TEST(BenchServer, ClientDisconnectHoldsTheBench) {
  FakeBench bench;
  ServerThread server(bench, {});
  {
    BenchClient client(ClientFor(server));
    client.Activate();
    ExecuteOne(client, 2.0);
  }  // destroyed without Deactivate: the socket just closes
  ASSERT_TRUE(Eventually([&] { return bench.holds.load() >= 1; }));
  EXPECT_EQ(bench.commands(), std::vector<double>{2.0});
}

TEST(BenchServer, StopEndsServeAndDeactivatesTheBench) {
  FakeBench bench;
  {
    ServerThread server(bench, {});
    BenchClient client(ClientFor(server));
    client.Activate();
    ExecuteOne(client, 1.0);
  }
  EXPECT_EQ(bench.activations.load(), 1);
  EXPECT_EQ(bench.deactivations.load(), 1);
}

}  // namespace
}  // namespace hybridtest::transfer
