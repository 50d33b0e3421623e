// HttpServer (monitor/http_server.h) on 127.0.0.1, and its parser: bounded heads (size and
// number of lines), bounded bodies, a deadline per request (a client that drips its head is
// cut off), a bounded connection table in which a newcomer is always read, and a Stop() that
// does not wait for clients.
#include <gtest/gtest.h>

#include <atomic>
#include <thread>
#include <vector>

#include "hybridtest/monitor/http_parse.h"
#include "hybridtest/monitor/http_server.h"
#include "monitor/raw_http.h"

namespace hybridtest::monitor {
namespace {

using testing::ConnectFrom;
using testing::ReadUntilClosed;
using testing::RequestFrom;
using testing::SendAll;
using testing::StatusOf;

TEST(HttpParse, ARequestWithItsQueryHeadersAndBody) {
  const std::string bytes =
      "POST /api/x?since=12&name=a%20b+c HTTP/1.1\r\nHost: h\r\nX-Thing:  v \r\n"
      "Content-Length: 3\r\n\r\nabcGET / HTTP/1.1\r\n\r\n";
  const ParseResult r = ParseRequest(bytes, HttpLimits{});
  ASSERT_EQ(r.status, ParseStatus::kComplete) << r.why;
  EXPECT_EQ(r.request.method, "POST");
  EXPECT_EQ(r.request.path, "/api/x");
  EXPECT_EQ(r.request.query.at("since"), "12");
  EXPECT_EQ(r.request.query.at("name"), "a b c");
  EXPECT_EQ(r.request.Header("x-thing"), "v");
  EXPECT_EQ(r.request.body, "abc");
  EXPECT_TRUE(r.keep_alive);
  // The next (pipelined) request follows.
  const ParseResult next = ParseRequest(std::string_view(bytes).substr(r.consumed), HttpLimits{});
  ASSERT_EQ(next.status, ParseStatus::kComplete);
  EXPECT_EQ(next.request.path, "/");
}

TEST(HttpParse, RefusesWhatIsNotHttpOrPassesTheLimits) {
  HttpLimits l;
  l.max_headers = 4;
  l.max_header_bytes = 256;
  l.max_body_bytes = 10;
  EXPECT_EQ(ParseRequest("GET /\r\n\r\n", l).status, ParseStatus::kBad);
  EXPECT_EQ(ParseRequest("\x16\x03\x01 garbage\r\n\r\n", l).status, ParseStatus::kBad);
  EXPECT_EQ(ParseRequest("GET / HTTP/1.1\r\nno colon\r\n\r\n", l).status, ParseStatus::kBad);
  EXPECT_EQ(ParseRequest("GET / HTTP/1.1\r\nA: 1\r\n", l).status, ParseStatus::kIncomplete);
  // Too many lines or bytes: refused before the head is whole.
  std::string many = "GET / HTTP/1.1\r\n";
  for (int i = 0; i < 5; ++i) many += "A: 1\r\n";
  EXPECT_EQ(ParseRequest(many, l).status, ParseStatus::kHeadTooLarge);
  EXPECT_EQ(ParseRequest("GET / HTTP/1.1\r\nA: " + std::string(300, 'x'), l).status,
            ParseStatus::kHeadTooLarge);
  EXPECT_EQ(ParseRequest("POST / HTTP/1.1\r\nContent-Length: 11\r\n\r\n", l).status,
            ParseStatus::kBodyTooLarge);
  EXPECT_EQ(ParseRequest("POST / HTTP/1.1\r\nContent-Length: -1\r\n\r\n", l).status,
            ParseStatus::kBad);
  EXPECT_EQ(ParseRequest("POST / HTTP/1.1\r\nTransfer-Encoding: chunked\r\n\r\n", l).status,
            ParseStatus::kUnsupported);
  EXPECT_FALSE(ParseRequest("GET / HTTP/1.0\r\n\r\n", l).keep_alive);
  EXPECT_FALSE(ParseRequest("GET / HTTP/1.1\r\nConnection: close\r\n\r\n", l).keep_alive);
}

struct Served {
  explicit Served(HttpLimits limits) : server("127.0.0.1", 0, limits) {
    server.Route("GET", "/hello", [](const HttpRequest&) {
      HttpResponse r;
      r.body = "hello";
      return r;
    });
    server.Start();
  }
  int port() const { return server.port(); }
  HttpServer server;
};

TEST(HttpServer, AHeaderFloodIsRefusedAndTheServerGoesOn) {
  Served s(HttpLimits{});
  // 200,000 header lines: the server answers 431 once past 64 lines and closes; the client
  // cannot send them all.
  const int fd = ConnectFrom("127.0.0.1", s.port());
  ASSERT_GE(fd, 0);
  ASSERT_TRUE(SendAll(fd, "GET /hello HTTP/1.1\r\n"));
  int lines_sent = 0;
  const std::string batch = [] {
    std::string b;
    for (int i = 0; i < 100; ++i) b += "X-Flood: " + std::string(100, 'f') + "\r\n";
    return b;
  }();
  while (lines_sent < 200000 && SendAll(fd, batch)) lines_sent += 100;
  const std::string answer = ReadUntilClosed(fd, 5.0);
  ::close(fd);
  // The refusal may be lost if the client's unread flood resets the connection; the count is
  // the server's own.
  if (!answer.empty()) {
    EXPECT_EQ(StatusOf(answer), 431) << answer;
  }
  EXPECT_LT(lines_sent, 200000) << "the server took the whole flood";
  EXPECT_GE(s.server.counters().too_large, 1);
  // One huge line too.
  const int fd2 = ConnectFrom("127.0.0.1", s.port());
  ASSERT_TRUE(SendAll(fd2, "GET /hello HTTP/1.1\r\nX-Big: " + std::string(20000, 'b')));
  EXPECT_EQ(StatusOf(ReadUntilClosed(fd2, 5.0)), 431);
  ::close(fd2);
  EXPECT_EQ(RequestFrom("127.0.0.1", s.port(), "GET", "/hello"), 200);
  EXPECT_EQ(RequestFrom("127.0.0.1", s.port(), "GET", "/nothing"), 404);
  EXPECT_EQ(RequestFrom("127.0.0.1", s.port(), "POST", "/hello"), 405);
}

TEST(HttpServer, AClientThatDripsItsHeadIsCutOff) {
  HttpLimits limits;
  limits.request_deadline = 1.0;
  Served s(limits);
  const int fd = ConnectFrom("127.0.0.1", s.port());
  ASSERT_TRUE(SendAll(fd, "GET /hello HTTP/1.1\r\n"));
  // One header line every 0.4 s for up to 10 s: the server closes it at its deadline.
  std::string answer;
  int dripped = 0;
  for (; dripped < 25; ++dripped) {
    answer = ReadUntilClosed(fd, 0.4);
    if (!answer.empty() || !SendAll(fd, "X-Drip: 1\r\n")) break;
  }
  ::close(fd);
  EXPECT_LT(dripped, 25) << "still connected after 10 s of dripping";
  if (!answer.empty()) {
    EXPECT_EQ(StatusOf(answer), 408) << answer;
  }
  EXPECT_GE(s.server.counters().timed_out, 1);
}

TEST(HttpServer, ANewcomerIsReadWhenTheTableIsFullAndStopDoesNotWaitForClients) {
  HttpLimits limits;
  limits.max_connections = 4;
  auto s = std::make_unique<Served>(limits);
  std::vector<int> idle;
  for (int i = 0; i < 10; ++i) {
    idle.push_back(ConnectFrom("127.0.0.1", s->port()));
    SendAll(idle.back(), "GET /hello HTTP/1.1\r\n");  // and nothing more
  }
  EXPECT_EQ(RequestFrom("127.0.0.1", s->port(), "GET", "/hello"), 200);
  EXPECT_GE(s->server.counters().evicted, 6);
  // Stop() with clients still connected (and silent): it closes them and returns.
  const auto t0 = std::chrono::steady_clock::now();
  s.reset();
  const double took = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  ::testing::Test::RecordProperty("stop_seconds", std::to_string(took));
  EXPECT_LT(took, 5.0);
  for (int fd : idle) ::close(fd);
}

}  // namespace
}  // namespace hybridtest::monitor
