// The three servers on the shared ServerLoop (transfer/server_loop.h) — the bench protocol
// (BenchServer), OpenFresco (openfresco::Server) and the ADS PLC emulator (AdsServer) — under
// the same abuse on 127.0.0.1, each followed by a real short run on the server (issue 45):
//  - a client dripping one byte every 100 ms never delays another client's exchange;
//  - idle clients flooding a server at a 64-file limit (a forked child): the run gets through
//    and the loop does not spin (its wake-ups are counted, not timed);
//  - a client claiming a routed AmsNetId from another address is not answered (ADS only: the
//    other protocols have no routes);
//  - a second client cannot command while a first does, and the first finishes.
// One adapter per protocol says how to serve the ideal emulated bench and open a client.
#include <gtest/gtest.h>
#include <netinet/in.h>
#include <sys/mman.h>
#include <sys/resource.h>
#include <sys/socket.h>
#include <sys/wait.h>
#include <unistd.h>

#include <csignal>
#include <functional>
#include <memory>
#include <new>
#include <ostream>
#include <thread>

#include "hybridtest/common/error.h"
#include "hybridtest/transfer/bench_client.h"
#include "hybridtest/transfer/bench_server.h"
#include "hybridtest/transfer/openfresco/client.h"
#include "hybridtest/transfer/openfresco/server.h"
#include "transfer/ads/ads_support.h"
#include "transfer/source_address.h"

namespace hybridtest::transfer {
namespace {

constexpr double kStep = 5e-5;  // one move of a run: 0.05 mm [m]

// One protocol's server of the ideal emulated bench (127.0.0.1, a free port), not yet serving.
class Served {
 public:
  virtual ~Served() = default;
  virtual std::uint16_t port() const = 0;
  virtual void Serve() = 0;
  virtual void Stop() = 0;
  virtual long turns() const = 0;  // the loop's wake-ups
  // A client of this server waiting at most `reply_timeout` [s] for an answer.
  virtual std::unique_ptr<TransferSystem> Client(double reply_timeout) const = 0;
  // The first bytes of a long frame (an opening for the protocols that have one).
  virtual std::vector<std::uint8_t> LongFrameStart() const = 0;
  // Sends a request from 127.0.0.9 claiming a routed identity; true if it was answered.
  // Protocols without routes: empty.
  std::function<bool(std::uint16_t port)> spoof;
};

EmulatedBenchSpec IdealSpec() { return LoadEmulatedBenchSpec(ads::testing::kIdealBench); }

// The safety of `hybridtest bench` for the bench protocol and OpenFresco.
BenchServerOptions BenchOptions(const EmulatedBenchSpec& spec, std::size_t max_connections) {
  BenchServerOptions o;
  o.port = 0;
  o.start_positions = {spec.actuators[0].p0};
  o.initial_stiffness = spec.stiffness(0, 0);
  o.max_connections = max_connections;
  return o;
}

class ServedBench final : public Served {
 public:
  explicit ServedBench(std::size_t max_connections)
      : spec_(IdealSpec()), bench_(MakeEmulatedBench(spec_)),
        server_(*bench_, BenchOptions(spec_, max_connections)) {}
  std::uint16_t port() const override { return server_.port(); }
  void Serve() override { server_.Serve(); }
  void Stop() override { server_.Stop(); }
  long turns() const override { return server_.loop_turns(); }
  std::unique_ptr<TransferSystem> Client(double reply_timeout) const override {
    BenchClientOptions o;
    o.port = server_.port();
    o.reply_timeout = reply_timeout;
    return std::make_unique<BenchClient>(o);
  }
  std::vector<std::uint8_t> LongFrameStart() const override {
    HelloMessage hello;
    hello.client_name = std::string(1000, 'x');
    return EncodeFrame(EncodeHello(1, hello));
  }

 private:
  EmulatedBenchSpec spec_;
  std::unique_ptr<TransferSystem> bench_;
  BenchServer server_;
};

class ServedOpenFresco final : public Served {
 public:
  explicit ServedOpenFresco(std::size_t max_connections)
      : spec_(IdealSpec()), bench_(MakeEmulatedBench(spec_)),
        server_(*bench_, Setup(spec_), BenchOptions(spec_, max_connections)) {}
  std::uint16_t port() const override { return server_.port(); }
  void Serve() override { server_.Serve(); }
  void Stop() override { server_.Stop(); }
  long turns() const override { return server_.loop_turns(); }
  std::unique_ptr<TransferSystem> Client(double reply_timeout) const override {
    openfresco::ClientOptions o;
    o.port = server_.port();
    o.reply_timeout = reply_timeout;
    return std::make_unique<openfresco::Client>(o);
  }
  std::vector<std::uint8_t> LongFrameStart() const override {
    return openfresco::EncodeTokenPreamble(std::string(1000, 'x'));
  }

 private:
  static openfresco::ExpSetup Setup(const EmulatedBenchSpec& spec) {
    openfresco::ExpSetup s;  // n = 1, T = [[1]]: the client's d is the offset from p0
    s.transform = {1.0};
    s.p0s = {spec.actuators[0].p0};
    s.stiffness_matrix = {spec.stiffness(0, 0)};
    return s;
  }
  EmulatedBenchSpec spec_;
  std::unique_ptr<TransferSystem> bench_;
  openfresco::Server server_;
};

class ServedAds final : public Served {
 public:
  static constexpr const char* kRouted = "10.0.0.7.1.1";  // the AmsNetId routed from 127.0.0.1
  explicit ServedAds(std::size_t max_connections)
      : spec_(IdealSpec()), bench_(MakeEmulatedBench(spec_)), server_(*bench_, [&] {
          ads::AdsServerOptions o;
          o.port = 0;
          ads::UseBenchSafety(o, spec_);
          o.max_connections = max_connections;
          o.routes = {ads::ParseAdsRoute(std::string(kRouted) + "@127.0.0.1", "test")};
          return o;
        }()) {
    spoof = [](std::uint16_t port) { return Spoof(port); };
  }
  std::uint16_t port() const override { return server_.port(); }
  void Serve() override { server_.Serve(); }
  void Stop() override { server_.Stop(); }
  long turns() const override { return server_.loop_turns(); }
  std::unique_ptr<TransferSystem> Client(double reply_timeout) const override {
    ads::AdsOptions o;
    o.endpoint.tcp_port = server_.port();
    o.endpoint.local_net_id = *ads::ParseAmsNetId(kRouted);  // routed from 127.0.0.1
    o.profile = ads::DefaultProfile(1);
    o.ack_timeout = 2.0;
    o.response_timeout = reply_timeout;
    return std::make_unique<ads::AdsTransfer>(o);
  }
  std::vector<std::uint8_t> LongFrameStart() const override {
    std::vector<std::uint8_t> bytes = {0, 0, 0xE8, 0x03, 0, 0};  // a prefix announcing 1000
    bytes.resize(64, 0);
    return bytes;
  }

 private:
  // From 127.0.0.9, a ReadState claiming the AmsNetId routed from 127.0.0.1.
  static bool Spoof(std::uint16_t port) {
    Socket s = testing::ConnectFrom("127.0.0.9", port);
    ads::AmsPacket request;
    request.header.target = {{{127, 0, 0, 1, 1, 1}}, ads::kPlcPort};
    request.header.source = {*ads::ParseAmsNetId(kRouted), 32905};
    request.header.command = ads::Command::kReadState;
    request.header.invoke_id = 1;
    if (!SendAll(s.fd(), ads::EncodePacket(request), 2.0)) return false;
    ads::Prefix prefix;
    std::vector<std::uint8_t> body;
    return ads::ReadAmsMessage(s.fd(), 5.0, prefix, body) == ReadStatus::kFrame;
  }
  EmulatedBenchSpec spec_;
  std::unique_ptr<TransferSystem> bench_;
  ads::AdsServer server_;
};

using Factory = std::function<std::unique_ptr<Served>(std::size_t max_connections)>;
struct Protocol {
  const char* name;
  Factory make;
};
void PrintTo(const Protocol& p, std::ostream* os) { *os << p.name; }

// Serves in a background thread while it lives.
class Serving {
 public:
  explicit Serving(Served& s) : served_(s), thread_([this] { served_.Serve(); }) {}
  ~Serving() {
    served_.Stop();
    thread_.join();
  }
  Serving(const Serving&) = delete;
  Serving& operator=(const Serving&) = delete;

 private:
  Served& served_;
  std::thread thread_;
};

// A short run: Activate, `steps` moves of kStep from where the actuator is (0 for a client
// that cannot read: OpenFresco's commands are offsets from p0). The last command.
double RunSteps(TransferSystem& client, int steps, double from = 0.0) {
  if (const auto now = client.ReadAll()) from = (*now)[0].position;
  double command = from;
  for (int i = 0; i < steps; ++i) {
    command += kStep;
    const Measurement m = ExecuteOne(client, command);
    EXPECT_NEAR(m.position, command, 1e-7) << "step " << i;
  }
  return command;
}

// Connects to 127.0.0.1:port without waiting (an idle client of a flood).
Socket StartConnect(std::uint16_t port) {
  Socket s(::socket(AF_INET, SOCK_STREAM | SOCK_NONBLOCK | SOCK_CLOEXEC, 0));
  sockaddr_in to{};
  to.sin_family = AF_INET;
  to.sin_port = htons(port);
  to.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  (void)::connect(s.fd(), reinterpret_cast<sockaddr*>(&to), sizeof to);
  return s;
}

class ServerAbuse : public ::testing::TestWithParam<Protocol> {};

TEST_P(ServerAbuse, ARunFinishesWhileAnotherClientDripsOneByteEvery100ms) {
  const auto served = GetParam().make(16);
  Serving serving(*served);
  std::atomic<bool> done{false};
  std::atomic<int> dripped{0};
  const std::vector<std::uint8_t> bytes = served->LongFrameStart();
  std::thread dripper([&] {
    Socket s = ConnectTcp("127.0.0.1", served->port(), 2.0);
    for (std::size_t i = 0; i < 40 && i < bytes.size() && !done.load(); ++i) {
      if (::send(s.fd(), &bytes[i], 1, MSG_NOSIGNAL) < 0) break;
      ++dripped;
      std::this_thread::sleep_for(std::chrono::milliseconds(100));
    }
  });
  for (int i = 0; i < 100 && dripped.load() < 2; ++i) {
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  // Replies within 1 s: a server stalled by the dripper (its frame deadline is 2 s) misses it.
  const auto client = served->Client(1.0);
  try {
    client->Activate();
    double at = RunSteps(*client, 3);
    for (int i = 0; i < 5; ++i) {
      std::this_thread::sleep_for(std::chrono::milliseconds(100));
      at = RunSteps(*client, 3, at);
    }
    client->Deactivate();
  } catch (const std::exception& e) {
    ADD_FAILURE() << "the run stopped while another client dripped: " << e.what();
  }
  RecordProperty("bytes_dripped_during_run", dripped.load());
  done = true;
  dripper.join();
  EXPECT_GE(dripped.load(), 2);
}

TEST_P(ServerAbuse, ARunFinishesWhileIdleClientsFloodAServerAtA64FileLimitAndItDoesNotSpin) {
  // The file limit, not the connection bound, is what the flood meets.
  const auto served = GetParam().make(200);
  // The child's wake-ups, in memory the parent shares.
  auto* turns = static_cast<std::atomic<long>*>(::mmap(nullptr, sizeof(std::atomic<long>),
                                                       PROT_READ | PROT_WRITE,
                                                       MAP_SHARED | MAP_ANONYMOUS, -1, 0));
  ASSERT_NE(turns, MAP_FAILED);
  new (turns) std::atomic<long>(0);
  const pid_t child = ::fork();
  ASSERT_GE(child, 0);
  if (child == 0) {
    rlimit rl{64, 64};
    if (::setrlimit(RLIMIT_NOFILE, &rl) != 0) ::_exit(98);
    std::thread count([&] {  // publishes the loop's wake-ups to the parent
      for (;;) {
        turns->store(served->turns());
        std::this_thread::sleep_for(std::chrono::milliseconds(10));
      }
    });
    count.detach();
    try {
      served->Serve();
    } catch (...) {
      ::_exit(97);
    }
    ::_exit(0);
  }
  std::vector<Socket> idle;
  for (int i = 0; i < 80; ++i) idle.push_back(StartConnect(served->port()));
  bool finished = false;
  std::string error;
  try {
    const auto client = served->Client(2.0);
    client->Activate();
    RunSteps(*client, 10);
    client->Deactivate();
    finished = true;
  } catch (const std::exception& e) {
    error = e.what();
  }
  // Still flooded: a loop polling a listener it cannot accept from would wake thousands of
  // times a second; this one waits its poll interval (100 ms) between tries.
  const long before = turns->load();
  std::this_thread::sleep_for(std::chrono::seconds(1));
  const long woke = turns->load() - before;
  ::kill(child, SIGKILL);
  int status = 0;
  ::waitpid(child, &status, 0);
  ::munmap(turns, sizeof(std::atomic<long>));
  RecordProperty("wakeups_in_a_second_of_flood", static_cast<int>(woke));
  EXPECT_TRUE(finished) << error;
  EXPECT_GT(woke, 0) << "the child's loop did not report its wake-ups";
  EXPECT_LT(woke, 1000) << "the loop spins at the file limit";
}

TEST_P(ServerAbuse, AClientClaimingARoutedIdentityFromAnotherAddressIsNotAnswered) {
  const auto served = GetParam().make(16);
  if (!served->spoof) GTEST_SKIP() << GetParam().name << " has no routes";
  Serving serving(*served);
  EXPECT_FALSE(served->spoof(served->port())) << "a spoofed AmsNetId was answered";
  const auto client = served->Client(1.0);
  client->Activate();
  RunSteps(*client, 3);
  client->Deactivate();
}

TEST_P(ServerAbuse, ASecondClientCannotCommandWhileTheFirstDoesAndTheFirstFinishes) {
  const auto served = GetParam().make(16);
  Serving serving(*served);
  const auto first = served->Client(2.0);
  first->Activate();
  const double at = RunSteps(*first, 3);  // the first client commands from now on
  const auto second = served->Client(0.5);
  const double far = at + 3e-3;  // within every safety limit: only the claim refuses it
  EXPECT_THROW(
      {
        second->Activate();
        ExecuteOne(*second, far);
      },
      Error);
  if (const auto now = first->ReadAll()) {
    EXPECT_NEAR((*now)[0].position, at, 1e-7) << "the second client moved the actuator";
  }
  EXPECT_NO_THROW(RunSteps(*first, 3, at));
  first->Deactivate();
}

INSTANTIATE_TEST_SUITE_P(
    Servers, ServerAbuse,
    ::testing::Values(
        Protocol{"bench", [](std::size_t n) -> std::unique_ptr<Served> {
                   return std::make_unique<ServedBench>(n);
                 }},
        Protocol{"openfresco", [](std::size_t n) -> std::unique_ptr<Served> {
                   return std::make_unique<ServedOpenFresco>(n);
                 }},
        Protocol{"ads", [](std::size_t n) -> std::unique_ptr<Served> {
                   return std::make_unique<ServedAds>(n);
                 }}),
    [](const ::testing::TestParamInfo<Protocol>& p) { return std::string(p.param.name); });

}  // namespace
}  // namespace hybridtest::transfer
