#pragma once
// HttpServer: the monitor's small HTTP/1.1 server, one thread, non-blocking sockets, every
// limit fixed in advance. cpp-httplib 0.11.4 (Debian 12) serves each connection on a pool
// thread until the client goes away: it bounds one header line but not their number, and its
// read timeout restarts at every byte, so a few clients that drip one header line every 2 s
// hold the whole pool, queue every later request (an operator's Stop too) and keep the
// process alive after the run. Here no client can hold anything:
//
//  - One thread polls every socket. A request is read whole (head and body) before it is
//    handled; a slow client costs one slot of the connection table, never a thread.
//  - Bounds: `max_header_bytes` for the request line and headers together, `max_headers`
//    header lines, `max_body_bytes` (Content-Length only; chunked bodies are refused). Past
//    them the client gets 431 or 413 and the connection is closed: memory per connection is
//    bounded, whatever is sent.
//  - Deadlines: a request must arrive whole within `request_deadline` of its first byte
//    (408 and closed otherwise), an idle keep-alive connection is closed after
//    `idle_timeout`, an answer must be taken within `write_deadline`, and a connection lives
//    at most `connection_lifetime` and `max_requests` requests.
//  - At most `max_connections` at once; a new connection beyond that closes the oldest one
//    that is still waiting for (or reading) a request, so that a newcomer (the operator) is
//    always read.
//  - Priority: the requests that are complete after one poll are handled routes marked
//    `priority` first (the operator's actions), then the others (viewers).
//  - Stop() is bounded: it closes every socket and joins the thread, whatever clients do.
#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <string>
#include <utility>
#include <vector>

namespace hybridtest::monitor {

struct HttpLimits {
  std::size_t max_connections = 128;
  std::size_t max_header_bytes = 8192;  // request line and header lines together. Unit: [B]
  std::size_t max_headers = 64;         // header lines
  std::size_t max_body_bytes = 4096;    // Unit: [B]
  double request_deadline = 2.0;        // first byte to whole request. Unit: [s]
  double idle_timeout = 5.0;            // keep-alive wait for a next request. Unit: [s]
  double write_deadline = 5.0;          // an answer taken whole. Unit: [s]
  double connection_lifetime = 60.0;    // Unit: [s]
  int max_requests = 200;               // per connection
};

struct HttpRequest {
  std::string method;  // "GET", "POST", ...
  std::string path;    // the target without its query
  std::map<std::string, std::string> query;  // decoded `a=b&c=d`
  std::vector<std::pair<std::string, std::string>> headers;  // names in lower case
  std::string body;
  std::string peer;  // the client's address ("127.0.0.1", "::1")
  // The first header `name` (lower case), or "".
  std::string Header(const std::string& name) const;
};

struct HttpResponse {
  int status = 200;
  std::string content_type = "text/plain";
  std::string body;
  std::vector<std::pair<std::string, std::string>> headers;
};

using HttpHandler = std::function<HttpResponse(const HttpRequest&)>;

// What the server refused, for tests and logs (monotonic counts).
struct HttpCounters {
  long served = 0;
  long too_large = 0;   // 431 and 413
  long timed_out = 0;   // 408, idle, write and lifetime closes
  long evicted = 0;     // closed to make room for a newcomer
  long malformed = 0;   // 400, 501
};

class HttpServer {
 public:
  // Binds `host`:`port` at once (port 0 picks one). Throws TransferError if it cannot.
  HttpServer(const std::string& host, std::uint16_t port, HttpLimits limits);
  ~HttpServer();  // Stop()
  HttpServer(const HttpServer&) = delete;
  HttpServer& operator=(const HttpServer&) = delete;

  std::uint16_t port() const { return port_; }

  // Before Start(): `method` `path` goes to `handler`; `priority` routes are handled first.
  void Route(const std::string& method, const std::string& path, HttpHandler handler,
             bool priority = false);
  // Serves on a thread of its own; `on_thread` runs first on it (e.g. to lower its priority).
  void Start(std::function<void()> on_thread = {});
  void Stop();
  HttpCounters counters() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
  std::uint16_t port_ = 0;
};

}  // namespace hybridtest::monitor
