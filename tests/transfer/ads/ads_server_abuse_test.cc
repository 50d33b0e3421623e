// The ADS PLC emulator (AdsServer) on the shared ServerLoop (transfer/server_loop.h) under
// abuse on 127.0.0.1 while a well-behaved run drives it: a client dripping one byte every
// 100 ms, idle clients flooding a server at a 64-file limit, a client claiming a routed
// AmsNetId from another address, a second client writing while the run commands. Each test
// asserts outcomes (the run finished, refusals, positions unchanged); every loop is bounded.
#include <gtest/gtest.h>
#include <sys/resource.h>
#include <sys/socket.h>
#include <sys/wait.h>
#include <netinet/in.h>
#include <unistd.h>

#include <csignal>
#include <dirent.h>
#include <thread>

#include "hybridtest/common/error.h"
#include "transfer/ads/ads_support.h"
#include "transfer/source_address.h"

namespace hybridtest::transfer::ads {
namespace {

using testing::kIdealBench;
using testing::ServedPlc;

// `steps` commands of 0.05 mm each from where the actuator is; the last measured position.
double RunSteps(AdsTransfer& ads, int steps) {
  const auto now = ads.ReadAll();
  if (!now) throw TransferError("the PLC could not be read");
  double position = (*now)[0].position;
  Measurement m;
  for (int i = 0; i < steps; ++i) {
    const double command = position + 0.05;
    ads.Execute(std::span<const double>(&command, 1), std::span<Measurement>(&m, 1));
    position = m.position;
  }
  return position;
}

// Connects to 127.0.0.1:port; an open socket, or a closed one if the connect failed.
Socket Connect(std::uint16_t port) {
  try {
    return ConnectTcp("127.0.0.1", port, 2.0);
  } catch (const Error&) {
    return Socket();
  }
}

// Starts a connection to 127.0.0.1:port without waiting for it (an idle client of a flood).
Socket StartConnect(std::uint16_t port) {
  Socket s(::socket(AF_INET, SOCK_STREAM | SOCK_NONBLOCK | SOCK_CLOEXEC, 0));
  sockaddr_in to{};
  to.sin_family = AF_INET;
  to.sin_port = htons(port);
  to.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  (void)::connect(s.fd(), reinterpret_cast<sockaddr*>(&to), sizeof to);
  return s;
}

TEST(AdsServerAbuse, ARunFinishesWhileAnotherClientDripsOneByteEvery100ms) {
  ServedPlc plc(kIdealBench);
  AdsOptions o = plc.Client();
  o.response_timeout = 1.0;  // a server stalled by the dripper (2 s before) misses it
  AdsTransfer ads(o);
  ads.Activate();
  std::atomic<bool> done{false};
  std::atomic<int> dripped{0};
  std::thread dripper([&] {
    Socket s = Connect(plc.server().port());
    // An AMS/TCP prefix announcing 32 bytes, then the bytes one at a time: a partial frame.
    const std::uint8_t bytes[] = {0, 0, 32, 0, 0, 0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10};
    for (int i = 0; i < 40 && !done.load(); ++i) {
      if (::send(s.fd(), &bytes[static_cast<std::size_t>(i) % sizeof bytes], 1, MSG_NOSIGNAL) < 0) break;
      ++dripped;
      std::this_thread::sleep_for(std::chrono::milliseconds(100));
    }
  });
  // The run starts once the drip has begun, and lasts while it drips (bounded loops).
  for (int i = 0; i < 100 && dripped.load() < 2; ++i) {
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  double last = 0.0;
  try {
    for (int i = 0; i < 20; ++i) {
      last = RunSteps(ads, 3);
      std::this_thread::sleep_for(std::chrono::milliseconds(50));
    }
  } catch (const std::exception& e) {
    ADD_FAILURE() << "the run stopped while another client dripped: " << e.what();
  }
  const int drips = dripped.load();
  done = true;
  dripper.join();
  RecordProperty("bytes_dripped_during_run", drips);
  EXPECT_GT(last, 0.0);
  ads.Deactivate();
}

TEST(AdsServerAbuse, ARunFinishesWhileIdleClientsFloodAServerAtA64FileLimit) {
  // The server in a child process whose file limit is 64; 80 idle clients connect first.
  EmulatedBenchSpec spec = LoadEmulatedBenchSpec(kIdealBench);
  std::unique_ptr<TransferSystem> bench = MakeEmulatedBench(spec);
  AdsServerOptions so;
  so.port = 0;
  UseBenchSafety(so, spec);
  so.max_connections = 200;  // the file limit, not the bound, is what the flood meets
  AdsServer server(*bench, so);
  const pid_t child = ::fork();
  ASSERT_GE(child, 0);
  if (child == 0) {
    rlimit rl{64, 64};
    if (::setrlimit(RLIMIT_NOFILE, &rl) != 0) ::_exit(98);
    try {
      server.Serve();
    } catch (...) {
      ::_exit(97);
    }
    ::_exit(0);
  }
  std::vector<Socket> idle;
  for (int i = 0; i < 80; ++i) idle.push_back(StartConnect(server.port()));
  AdsOptions o;
  o.endpoint.tcp_port = server.port();
  o.profile = DefaultProfile(1);
  o.ack_timeout = 2.0;
  bool finished = false;
  std::string error;
  try {
    AdsTransfer ads(o);
    ads.Activate();
    RunSteps(ads, 10);
    ads.Deactivate();
    finished = true;
  } catch (const std::exception& e) {
    error = e.what();
  }
  ::kill(child, SIGKILL);
  int status = 0;
  ::waitpid(child, &status, 0);
  EXPECT_TRUE(finished) << error;
}

TEST(AdsServerAbuse, AClientClaimingARoutedAmsNetIdFromAnotherAddressIsClosed) {
  const auto routed = *ParseAmsNetId("10.0.0.7.1.1");
  ServedPlc plc(kIdealBench, [](AdsServerOptions& o) {
    o.routes = {ParseAdsRoute("10.0.0.7.1.1@127.0.0.1", "test")};
  });
  // The spoofer: from 127.0.0.9, a ReadState claiming the routed AmsNetId.
  Socket s = transfer::testing::ConnectFrom("127.0.0.9", plc.server().port());
  AmsPacket request;
  request.header.target = {{{127, 0, 0, 1, 1, 1}}, kPlcPort};
  request.header.source = {routed, 32905};
  request.header.command = Command::kReadState;
  request.header.invoke_id = 1;
  ASSERT_TRUE(SendAll(s.fd(), EncodePacket(request), 2.0));
  Prefix prefix;
  std::vector<std::uint8_t> body;
  EXPECT_EQ(ReadAmsMessage(s.fd(), 5.0, prefix, body), ReadStatus::kClosed)
      << "a spoofed AmsNetId was answered";
  // The same AmsNetId from its route's address is served.
  AdsOptions o = plc.Client();
  o.endpoint.local_net_id = routed;
  AdsTransfer ok(o);
  EXPECT_NO_THROW(ok.Activate());
}

TEST(AdsServerAbuse, ASecondClientCannotWriteWhileTheRunCommandsAndTheRunFinishes) {
  ServedPlc plc(kIdealBench);
  AdsTransfer run(plc.Client());
  run.Activate();
  const double before = RunSteps(run, 3);
  run.Hold();
  AdsOptions other_options = plc.Client();
  other_options.ack_timeout = 0.5;
  AdsTransfer other(other_options);
  const double far = before + 3.0;
  Measurement m;
  EXPECT_THROW(
      {
        other.Activate();
        other.Execute(std::span<const double>(&far, 1), std::span<Measurement>(&m, 1));
      },
      Error);
  run.Activate();  // resumes without moving; ReadAll refuses a holding PLC
  const auto seen = run.ReadAll();
  ASSERT_TRUE(seen.has_value());
  EXPECT_EQ((*seen)[0].position, before) << "the second client moved the actuator";
  EXPECT_NO_THROW(RunSteps(run, 3));
  run.Deactivate();
}

}  // namespace
}  // namespace hybridtest::transfer::ads
