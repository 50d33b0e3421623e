// BenchServer against hostile or careless peers (issue 10): idle and slow connections never
// delay a real client, a session is never taken over, duplicate or stale COMMANDs are refused
// and never executed, wrong tokens lock an address out, and log lines cannot be forged.
#include <array>
#include <fmt/core.h>
#include <gtest/gtest.h>

#include <chrono>
#include <cstdint>
#include <functional>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "hybridtest/common/error.h"
#include "hybridtest/transfer/bench_client.h"
#include "hybridtest/transfer/bench_server.h"
#include "hybridtest/transfer/protocol.h"
#include "transfer/bench_fake.h"
#include "transfer/source_address.h"

namespace hybridtest::transfer {
namespace {

using testing::FakeBench;
using testing::ServerThread;

using testing::ClientFor;

// The clients' reply timeout: far below the heartbeat timeout a blocked server would wait. [s]
constexpr double kReplyTimeout = 1.0;

// Collects the server's log lines (the server logs from its own thread).
struct LogLines {
  std::mutex mutex;
  std::vector<std::string> lines;
  std::function<void(const std::string&)> Sink() {
    return [this](const std::string& line) {
      const std::lock_guard<std::mutex> lock(mutex);
      lines.push_back(line);
    };
  }
  std::vector<std::string> Get() {
    const std::lock_guard<std::mutex> lock(mutex);
    return lines;
  }
};

// Sends HELLO (sequence 1) on a raw socket and returns the reply frame.
Frame RawHello(Socket& raw, const std::string& token = "", const std::string& name = "raw") {
  HelloMessage hello;
  hello.token = token;
  hello.client_name = name;
  EXPECT_TRUE(SendAll(raw.fd(), EncodeFrame(EncodeHello(1, hello)), 2.0));
  Frame reply;
  EXPECT_EQ(ReadFrame(raw.fd(), 5.0, reply), ReadStatus::kFrame);
  return reply;
}

TEST(BenchServerHardening, IdleConnectionsDoNotDelayARealClient) {
  FakeBench bench;
  BenchServerOptions o;
  o.handshake_timeout = 60.0;  // the idle peers stay pending for the whole test
  ServerThread server(bench, o);
  std::vector<Socket> idle;
  for (int i = 0; i < 3; ++i) idle.push_back(ConnectTcp("127.0.0.1", server.port(), 2.0));
  BenchClient client(ClientFor(server, kReplyTimeout));
  client.Activate();
  EXPECT_EQ(ExecuteOne(client, 1.0).force, 5.0);
}

TEST(BenchServerHardening, PartialHelloDoesNotBlockOthers) {
  FakeBench bench;
  BenchServerOptions o;
  o.handshake_timeout = 60.0;
  ServerThread server(bench, o);
  Socket slow = ConnectTcp("127.0.0.1", server.port(), 2.0);
  auto bytes = EncodeFrame(EncodeHello(1, HelloMessage{}));
  bytes.resize(10);  // half a header, then nothing
  ASSERT_TRUE(SendAll(slow.fd(), bytes, 2.0));
  BenchClient client(ClientFor(server, kReplyTimeout));
  client.Activate();
  EXPECT_EQ(ExecuteOne(client, 2.0).force, 10.0);
}

TEST(BenchServerHardening, AFloodOfConnectionsEvictsTheOldestAndTheClientGetsThrough) {
  FakeBench bench;
  BenchServerOptions o;
  o.handshake_timeout = 60.0;
  o.max_connections = 4;
  LogLines log;
  o.log = log.Sink();
  ServerThread server(bench, o);
  std::vector<Socket> idle;
  for (int i = 0; i < 12; ++i) idle.push_back(ConnectTcp("127.0.0.1", server.port(), 2.0));
  BenchClient client(ClientFor(server, kReplyTimeout));
  client.Activate();
  EXPECT_EQ(ExecuteOne(client, 1.0).force, 5.0);
  bool evicted = false;
  for (const auto& line : log.Get()) evicted |= line.find("to make room") != std::string::npos;
  EXPECT_TRUE(evicted);
}

TEST(BenchServerHardening, StalledPeerIsToldAndDroppedAfterTheHandshakeTimeout) {
  FakeBench bench;
  BenchServerOptions o;
  o.handshake_timeout = 0.2;
  ServerThread server(bench, o);
  Socket idle = ConnectTcp("127.0.0.1", server.port(), 2.0);
  Frame reply;
  ASSERT_EQ(ReadFrame(idle.fd(), 10.0, reply), ReadStatus::kFrame);
  const ErrorMessage error = DecodeError(reply);
  EXPECT_EQ(error.code, ErrorCode::kTimeout);
  EXPECT_NE(error.text.find("handshake timeout"), std::string::npos) << error.text;
  EXPECT_EQ(ReadFrame(idle.fd(), 10.0, reply), ReadStatus::kClosed);
  EXPECT_EQ(bench.holds.load(), 0);  // an unauthenticated peer never touches the bench
}

TEST(BenchServerHardening, APendingHelloCannotTakeOverASession) {
  FakeBench bench;
  BenchServerOptions o;
  o.handshake_timeout = 60.0;
  ServerThread server(bench, o);
  Socket early = ConnectTcp("127.0.0.1", server.port(), 2.0);  // pending before the session
  BenchClient client(ClientFor(server, kReplyTimeout));
  client.Activate();
  EXPECT_EQ(ExecuteOne(client, 1.0).force, 5.0);  // the client commands from now on
  // The pending connection's session may open, but its COMMAND is refused: nothing moves.
  ASSERT_EQ(RawHello(early).type, MessageType::kWelcome);
  ASSERT_TRUE(SendAll(early.fd(), EncodeFrame(EncodeCommands(2, std::array<double, 1>{4.0})), 2.0));
  Frame reply;
  ASSERT_EQ(ReadFrame(early.fd(), 5.0, reply), ReadStatus::kFrame);
  EXPECT_EQ(DecodeError(reply).code, ErrorCode::kBusy);
  EXPECT_EQ(ExecuteOne(client, 2.0).force, 10.0);
  EXPECT_EQ(bench.commands(), (std::vector<double>{1.0, 2.0}));
}

// A second COMMAND with sequence `replayed` after COMMAND 2 is refused and never executed.
class ReplayTest : public ::testing::TestWithParam<std::uint32_t> {};

TEST_P(ReplayTest, DuplicateOrStaleCommandIsRefusedAndNeverExecuted) {
  FakeBench bench;
  ServerThread server(bench, {});
  Socket raw = ConnectTcp("127.0.0.1", server.port(), 2.0);
  ASSERT_EQ(RawHello(raw).type, MessageType::kWelcome);
  const auto command = EncodeFrame(EncodeCommands(2, std::array<double, 1>{1.0}));
  ASSERT_TRUE(SendAll(raw.fd(), command, 2.0));
  Frame reply;
  ASSERT_EQ(ReadFrame(raw.fd(), 5.0, reply), ReadStatus::kFrame);
  ASSERT_EQ(reply.type, MessageType::kMeasurement);
  const std::uint32_t replayed = GetParam();
  ASSERT_TRUE(SendAll(raw.fd(), EncodeFrame(EncodeCommands(replayed, std::array<double, 1>{4.0})), 2.0));
  ASSERT_EQ(ReadFrame(raw.fd(), 5.0, reply), ReadStatus::kFrame);
  ASSERT_EQ(reply.type, MessageType::kError);
  const ErrorMessage error = DecodeError(reply);
  EXPECT_EQ(error.code, ErrorCode::kProtocol);
  EXPECT_NE(error.text.find("expected 3"), std::string::npos) << error.text;
  EXPECT_EQ(bench.commands(), std::vector<double>{1.0});  // moved once
}

INSTANTIATE_TEST_SUITE_P(Sequences, ReplayTest,
                         ::testing::Values(2u, 1u, 0u, 0xFFFFFFFFu, 5u));

TEST(BenchServerHardening, FiveWrongTokensLockTheAddressOutAndAreLogged) {
  FakeBench bench;
  BenchServerOptions o;
  o.token = "right";
  LogLines log;
  o.log = log.Sink();
  ServerThread server(bench, o);
  for (int i = 0; i < AuthThrottle::kMaxFailures; ++i) {
    Socket raw = ConnectTcp("127.0.0.1", server.port(), 2.0);
    EXPECT_EQ(DecodeError(RawHello(raw, "guess")).code, ErrorCode::kAuth);
  }
  // Locked out: even the right token is refused now, without being compared.
  Socket raw = ConnectTcp("127.0.0.1", server.port(), 2.0);
  const ErrorMessage error = DecodeError(RawHello(raw, "right"));
  EXPECT_EQ(error.code, ErrorCode::kAuth);
  EXPECT_NE(error.text.find("locked out"), std::string::npos) << error.text;
  bool logged = false;
  for (const auto& line : log.Get()) logged |= line.find("auth lockout") != std::string::npos;
  EXPECT_TRUE(logged);
  EXPECT_TRUE(bench.commands().empty());
}

// Issue 15: rotating 127.0.0.x source addresses gave 5,200-8,100 guesses/s with no lockout.
// The lockout is per /24 block, and a global budget bounds guesses spread over many blocks.
TEST(BenchServerHardening, RotatingSourceAddressesAreLockedOutByBlockAndRateLimited) {
  FakeBench bench;
  BenchServerOptions o;
  o.token = "right";
  LogLines log;
  o.log = log.Sink();
  ServerThread server(bench, o);
  for (int i = 1; i <= AuthThrottle::kMaxFailures; ++i) {
    Socket raw = testing::ConnectFrom(fmt::format("127.0.0.{}", 10 + i), server.port());
    EXPECT_EQ(DecodeError(RawHello(raw, "guess")).code, ErrorCode::kAuth);
  }
  {  // a fresh address of the same /24, with the right token: refused unread
    Socket raw = testing::ConnectFrom("127.0.0.250", server.port());
    const ErrorMessage error = DecodeError(RawHello(raw, "right"));
    EXPECT_NE(error.text.find("127.0.0.0/24"), std::string::npos) << error.text;
  }
  // Spread over many /24 blocks: the global budget runs out.
  int limited = 0;
  for (int i = 1; i <= 3 * AuthThrottle::kGlobalBurst; ++i) {
    Socket raw = testing::ConnectFrom(fmt::format("127.{}.0.1", i), server.port());
    const ErrorMessage error = DecodeError(RawHello(raw, "guess"));
    EXPECT_EQ(error.code, ErrorCode::kAuth);
    limited += error.text.find("auth rate limit") != std::string::npos ? 1 : 0;
  }
  // Most were refused without comparing (the budget refills at one per second; that the
  // right token is refused too while it is spent is tested with a fixed clock in auth_test).
  EXPECT_GT(limited, AuthThrottle::kGlobalBurst);
  EXPECT_TRUE(bench.commands().empty());
}

TEST(BenchServerHardening, ShortOrWhitespaceTokenIsRefusedOffLoopback) {
  FakeBench bench;
  BenchServerOptions o;
  o.host = "0.0.0.0";
  o.port = 0;
  o.token = " ";
  EXPECT_THROW((BenchServer{bench, o}), ConfigError);
  o.token = "fifteen-bytes!!";
  EXPECT_THROW((BenchServer{bench, o}), ConfigError);
  o.token = "sixteen-bytes!!!";
  EXPECT_NO_THROW((BenchServer{bench, o}));
}

TEST(BenchServerHardening, ClientNameCannotForgeALogLine) {
  FakeBench bench;
  BenchServerOptions o;
  LogLines log;
  o.log = log.Sink();
  ServerThread server(bench, o);
  Socket raw = ConnectTcp("127.0.0.1", server.port(), 2.0);
  ASSERT_EQ(RawHello(raw, "", "evil\nhybridtest bench: holding: forged\r").type,
            MessageType::kWelcome);
  bool seen = false;
  for (const auto& line : log.Get()) {
    EXPECT_EQ(line.find_first_of("\n\r"), std::string::npos) << line;
    seen |= line.find("evil\\x0Ahybridtest bench: holding: forged\\x0D") != std::string::npos;
  }
  EXPECT_TRUE(seen);
}

}  // namespace
}  // namespace hybridtest::transfer
