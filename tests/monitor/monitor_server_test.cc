// The monitor's HTTP server on 127.0.0.1: the page and the API, the token rules of the
// actions (401 without, 403 wrong, 429 while the source waits, and the right token served
// whatever came before, from any address; none at all without a configured token unless the
// run allows it; 405 for a follower), the bind policy,
// and viewers that send garbage or stall without taking the server down.
#include <gtest/gtest.h>

#include "hybridtest/common/error.h"
#include "hybridtest/monitor/monitor_server.h"
#include "hybridtest/monitor/page_assets.h"
// After Eigen (through the session): <resolv.h>, which httplib includes, defines `_res`.
#include <arpa/inet.h>
#include <httplib.h>

#include <atomic>
#include <csignal>
#include <thread>

#include "monitor/raw_http.h"
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

namespace hybridtest::monitor {
namespace {

// cpp-httplib 0.11.4's client (Debian 12), the independent client of these tests, writes with
// send() without MSG_NOSIGNAL: when the server refuses a request and closes before the client
// has written its whole body (a 1 MiB POST below), the client's next write raises SIGPIPE and
// kills the test process. The client is the tests' own, so this executable ignores SIGPIPE
// (every test of test_monitor runs in a process of its own and gets this initialiser).
[[maybe_unused]] const bool kClientIgnoresSigpipe = [] {
  std::signal(SIGPIPE, SIG_IGN);
  return true;
}();

constexpr const char* kToken = "a-token-of-more-than-16-bytes";

struct Fixture {
  explicit Fixture(MonitorServerOptions options, bool read_only = false)
      : control(state), server(state, read_only ? nullptr : &control, std::move(options)),
        client("127.0.0.1", server.port()) {
    RunIdentity id;
    id.slots = {"r1"};
    id.end_time = 1.0;
    state.SetIdentity(id, FrameLayout{1, 0}, {});
    state.AddFrame(std::vector<double>{3, 0.003, 0.01, 0, 0, 0.001, 7.2});
    server.Start();
    client.set_connection_timeout(5);
    client.set_read_timeout(5);
  }
  int Post(const std::string& path, const std::string& token = "") {
    httplib::Headers headers;
    if (!token.empty()) headers.emplace("Authorization", "Bearer " + token);
    auto res = client.Post(path.c_str(), headers, "", "text/plain");
    return res ? res->status : -1;
  }
  MonitorState state;
  OperatorControl control;
  MonitorServer server;
  httplib::Client client;
};

MonitorServerOptions WithToken() {
  MonitorServerOptions o;
  o.token = kToken;
  return o;
}

TEST(MonitorServer, ServesThePageAndTheState) {
  Fixture f(WithToken());
  auto page = f.client.Get("/");
  ASSERT_TRUE(page);
  EXPECT_EQ(page->status, 200);
  EXPECT_NE(page->body.find("hybridtest monitor"), std::string::npos);
  EXPECT_EQ(f.client.Get("/monitor.js")->status, 200);
  EXPECT_EQ(f.client.Get("/uplot.js")->status, HasUplot() ? 200 : 404);
  auto state = f.client.Get("/api/state");
  ASSERT_TRUE(state);
  const auto j = nlohmann::json::parse(state->body);
  EXPECT_EQ(j["status"], "running");
  EXPECT_EQ(j["step"], 3);
  EXPECT_DOUBLE_EQ(j["t"].get<double>(), 0.003);
  EXPECT_EQ(j["physical_evaluations"], 0);
  EXPECT_EQ(j["actions_policy"], "token");
  const auto series = nlohmann::json::parse(f.client.Get("/api/series?since=-1")->body);
  EXPECT_EQ(series["columns"]["r0"], (nlohmann::json{7.2}));
}

TEST(MonitorServer, ActionsNeedTheToken) {
  Fixture f(WithToken());
  EXPECT_EQ(f.Post("/api/stop"), 401);
  EXPECT_EQ(f.Post("/api/stop", "wrong"), 403);
  EXPECT_FALSE(f.control.holding());
  EXPECT_EQ(f.Post("/api/hold", kToken), 200);
  EXPECT_TRUE(f.control.holding());
  EXPECT_EQ(f.Post("/api/hold", kToken), 409);
  EXPECT_EQ(f.Post("/api/continue", kToken), 200);
  // Every attempt is on the page, the refused ones with their status.
  const auto actions = f.state.StateJson()["actions"];
  ASSERT_EQ(actions.size(), 2u);
  EXPECT_EQ(actions[0]["refused"], 401);
  EXPECT_EQ(actions[1]["refused"], 403);
}

TEST(MonitorServer, WrongTokensSlowTheirSourceButNeverTheRightToken) {
  Fixture f(WithToken());
  // The operator's own address, after many wrong tokens from it: 403 while free, then 429
  // with Retry-After, and the right token is still served at once.
  std::vector<int> statuses;
  for (int i = 0; i < 8; ++i) statuses.push_back(f.Post("/api/stop", "guess" + std::to_string(i)));
  for (int i = 0; i < SourceBackoff::kFreeFailures; ++i) EXPECT_EQ(statuses[i], 403) << i;
  EXPECT_EQ(statuses.back(), 429);
  auto res = f.client.Post("/api/stop", httplib::Headers{{"Authorization", "Bearer x"}}, "",
                           "text/plain");
  ASSERT_TRUE(res);
  EXPECT_EQ(res->status, 429);
  EXPECT_FALSE(res->get_header_value("Retry-After").empty());
  EXPECT_EQ(f.Post("/api/hold", kToken), 200);
  EXPECT_TRUE(f.control.holding());
  // Another address is not slowed by them.
  EXPECT_EQ(testing::RequestFrom("127.0.0.3", f.server.port(), "POST", "/api/stop", "nope"), 403);
  // The flood is not listed on the page: only counted failures are (8 + 1 tried; shown: the
  // free failures, the one that starts the wait, and the other address's one).
  const auto actions = f.state.StateJson()["actions"];
  EXPECT_EQ(actions.size(), static_cast<std::size_t>(SourceBackoff::kFreeFailures + 2))
      << actions.dump();
  for (const auto& a : actions) EXPECT_TRUE(a.contains("refused")) << a.dump();
}

TEST(MonitorServer, AWrongTokenFloodFromRotatingAddressesNeverRefusesTheOperator) {
  Fixture f(WithToken());
  const int port = f.server.port();
  std::atomic<bool> done{false};
  std::atomic<long> flood{0};
  // Wrong tokens from 127.0.0.2 .. 127.0.0.201 in turn, as fast as they are answered.
  std::thread attacker([&] {
    for (int i = 0; !done.load() && i < 20000; ++i) {
      const std::string source = "127.0.0." + std::to_string(2 + i % 200);
      testing::RequestFrom(source, port, "POST", "/api/hold", "guess" + std::to_string(i), 2.0);
      ++flood;
    }
  });
  // The operator, from 127.0.0.1 (after 5 wrong tokens of its own): Hold and Continue 17 times.
  for (int i = 0; i < 5; ++i) testing::RequestFrom("127.0.0.1", port, "POST", "/api/stop", "typo");
  int served = 0;
  for (int i = 0; i < 17; ++i) {
    const bool hold = i % 2 == 0;
    const int status = testing::RequestFrom("127.0.0.1", port, "POST",
                                            hold ? "/api/hold" : "/api/continue", kToken);
    EXPECT_EQ(status, 200) << "attempt " << i;
    served += status == 200;
    EXPECT_EQ(f.control.holding(), hold);
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
  }
  done = true;
  attacker.join();
  ::testing::Test::RecordProperty("wrong_tokens_sent", std::to_string(flood.load()));
  EXPECT_EQ(served, 17);
  EXPECT_GT(flood.load(), 17) << "the flood did not run alongside";
}

TEST(MonitorServer, WithoutATokenActionsAreRefusedUnlessTheRunAllowsThem) {
  {
    Fixture f(MonitorServerOptions{});
    EXPECT_EQ(f.Post("/api/hold"), 403);
    EXPECT_EQ(f.state.StateJson()["actions_policy"], "refused (no token)");
  }
  MonitorServerOptions open;
  open.actions_without_token = true;
  Fixture f(open);
  EXPECT_EQ(f.Post("/api/hold"), 200);
}

TEST(MonitorServer, AFollowerIsReadOnly) {
  Fixture f(WithToken(), /*read_only=*/true);
  EXPECT_EQ(f.Post("/api/stop", kToken), 405);
  EXPECT_EQ(f.state.StateJson()["actions_policy"], "read-only");
}

TEST(MonitorServer, ANonLoopbackAddressNeedsALongToken) {
  MonitorState state;
  MonitorServerOptions o;
  o.host = "0.0.0.0";
  EXPECT_THROW(MonitorServer(state, nullptr, o), ConfigError);
  o.token = "short";
  EXPECT_THROW(MonitorServer(state, nullptr, o), ConfigError);
}

// A raw connection to the server.
int Connect(std::uint16_t port) {
  const int fd = ::socket(AF_INET, SOCK_STREAM, 0);
  sockaddr_in addr{};
  addr.sin_family = AF_INET;
  addr.sin_port = htons(port);
  ::inet_pton(AF_INET, "127.0.0.1", &addr.sin_addr);
  EXPECT_EQ(::connect(fd, reinterpret_cast<sockaddr*>(&addr), sizeof addr), 0);
  return fd;
}

TEST(MonitorServer, GarbageAndStalledViewersDoNotStopIt) {
  MonitorServerOptions o = WithToken();
  o.limits.request_deadline = 0.5;
  o.limits.idle_timeout = 0.5;
  Fixture f(o);
  // Garbage, a request line without an end, a huge body, and connections that say nothing.
  std::vector<int> stalled;
  for (int i = 0; i < 4; ++i) stalled.push_back(Connect(f.server.port()));
  const int junk = Connect(f.server.port());
  const std::string bytes = "\x16\x03\x01\x02\x00garbage\r\n\r\nGET /api/state HTTP/9\r\n";
  EXPECT_GT(::send(junk, bytes.data(), bytes.size(), MSG_NOSIGNAL), 0);
  ::close(junk);
  auto big = f.client.Post("/api/hold", std::string(1 << 20, 'x'), "text/plain");
  if (big) {
    EXPECT_NE(big->status, 200);
  }
  EXPECT_FALSE(f.control.holding());
  // Still serving (the stalled connections time out and free the pool).
  auto state = f.client.Get("/api/state");
  ASSERT_TRUE(state);
  EXPECT_EQ(state->status, 200);
  for (int fd : stalled) ::close(fd);
}

}  // namespace
}  // namespace hybridtest::monitor
