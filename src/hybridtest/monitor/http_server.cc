// See http_server.h.
#include "hybridtest/monitor/http_server.h"

#include <arpa/inet.h>
#include <fcntl.h>
#include <fmt/core.h>
#include <netdb.h>
#include <netinet/in.h>
#include <poll.h>
#include <sys/eventfd.h>
#include <sys/socket.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cerrno>
#include <chrono>
#include <cstring>
#include <list>
#include <mutex>
#include <thread>

#include "hybridtest/common/error.h"
#include "hybridtest/monitor/http_parse.h"

namespace hybridtest::monitor {
namespace {

using Clock = std::chrono::steady_clock;

Clock::duration Seconds(double s) {
  return std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(s));
}

const char* Reason(int status) {
  switch (status) {
    case 200: return "OK";
    case 400: return "Bad Request";
    case 401: return "Unauthorized";
    case 403: return "Forbidden";
    case 404: return "Not Found";
    case 405: return "Method Not Allowed";
    case 408: return "Request Timeout";
    case 409: return "Conflict";
    case 413: return "Content Too Large";
    case 429: return "Too Many Requests";
    case 431: return "Request Header Fields Too Large";
    case 501: return "Not Implemented";
    case 503: return "Service Unavailable";
    default: return "Status";
  }
}

std::string Serialize(const HttpResponse& res, bool keep_alive) {
  std::string out = fmt::format("HTTP/1.1 {} {}\r\nContent-Type: {}\r\nContent-Length: {}\r\n",
                                res.status, Reason(res.status), res.content_type, res.body.size());
  for (const auto& [name, value] : res.headers) out += name + ": " + value + "\r\n";
  out += keep_alive ? "Connection: keep-alive\r\n\r\n" : "Connection: close\r\n\r\n";
  out += res.body;
  return out;
}

std::string PeerAddress(const sockaddr_storage& addr) {
  char text[INET6_ADDRSTRLEN] = {};
  if (addr.ss_family == AF_INET) {
    ::inet_ntop(AF_INET, &reinterpret_cast<const sockaddr_in&>(addr).sin_addr, text, sizeof text);
  } else if (addr.ss_family == AF_INET6) {
    ::inet_ntop(AF_INET6, &reinterpret_cast<const sockaddr_in6&>(addr).sin6_addr, text,
                sizeof text);
  }
  std::string peer = text;
  if (peer.rfind("::ffff:", 0) == 0 && peer.find('.') != std::string::npos) peer.erase(0, 7);
  return peer;
}

struct Connection {
  int fd = -1;
  std::string peer;
  std::string in;   // bytes received, not yet a whole request
  std::string out;  // the answer being sent
  std::size_t sent = 0;
  bool writing = false;
  bool close_after = false;
  int requests = 0;
  Clock::time_point opened;
  Clock::time_point deadline;  // of the phase it is in
  bool receiving = false;      // a request has begun
};

struct RouteEntry {
  std::string method, path;
  HttpHandler handler;
  bool priority = false;
};

}  // namespace

std::string HttpRequest::Header(const std::string& name) const {
  for (const auto& [n, v] : headers) {
    if (n == name) return v;
  }
  return {};
}

struct HttpServer::Impl {
  HttpLimits limits;
  int listen_fd = -1;
  int wake_fd = -1;
  std::vector<RouteEntry> routes;
  std::list<Connection> connections;
  std::atomic<bool> stop{false};
  std::thread thread;
  mutable std::mutex counters_mutex;
  HttpCounters counters;

  void Count(long HttpCounters::*field) {
    std::lock_guard lock(counters_mutex);
    ++(counters.*field);
  }
  void Close(std::list<Connection>::iterator c) {
    ::close(c->fd);
    connections.erase(c);
  }
  // Queues `res` on `c` (and sends what the socket takes now).
  void Answer(Connection& c, const HttpResponse& res, bool keep_alive) {
    c.out = Serialize(res, keep_alive);
    c.sent = 0;
    c.writing = true;
    c.close_after = !keep_alive;
    c.deadline = Clock::now() + Seconds(limits.write_deadline);
    Flush(c);
  }
  // Sends what the socket takes; true while the connection is still good.
  bool Flush(Connection& c) {
    while (c.sent < c.out.size()) {
      const ssize_t n = ::send(c.fd, c.out.data() + c.sent, c.out.size() - c.sent, MSG_NOSIGNAL);
      if (n > 0) {
        c.sent += static_cast<std::size_t>(n);
      } else if (n < 0 && (errno == EAGAIN || errno == EWOULDBLOCK)) {
        return true;
      } else if (n < 0 && errno == EINTR) {
        continue;
      } else {
        return false;
      }
    }
    return true;
  }
  void Accept();
  void Loop();
  HttpResponse Dispatch(const HttpRequest& req) const;
};

HttpResponse HttpServer::Impl::Dispatch(const HttpRequest& req) const {
  bool path_known = false;
  for (const RouteEntry& r : routes) {
    if (r.path != req.path) continue;
    path_known = true;
    if (r.method == req.method) return r.handler(req);
  }
  HttpResponse res;
  res.status = path_known ? 405 : 404;
  res.body = path_known ? "method not allowed on " + req.path + "\n" : "no such page\n";
  return res;
}

void HttpServer::Impl::Accept() {
  for (int i = 0; i < 64; ++i) {
    sockaddr_storage addr{};
    socklen_t len = sizeof addr;
    const int fd = ::accept4(listen_fd, reinterpret_cast<sockaddr*>(&addr), &len,
                             SOCK_NONBLOCK | SOCK_CLOEXEC);
    if (fd < 0) return;  // EAGAIN (nothing more), or a transient error: next poll
    if (connections.size() >= limits.max_connections) {
      // Room for the newcomer: the oldest connection that is not sending an answer.
      auto oldest = connections.end();
      for (auto it = connections.begin(); it != connections.end(); ++it) {
        if (!it->writing && (oldest == connections.end() || it->opened < oldest->opened)) {
          oldest = it;
        }
      }
      if (oldest == connections.end()) {
        ::close(fd);
        Count(&HttpCounters::evicted);
        continue;
      }
      Close(oldest);
      Count(&HttpCounters::evicted);
    }
    Connection c;
    c.fd = fd;
    c.peer = PeerAddress(addr);
    c.opened = Clock::now();
    c.deadline = c.opened + Seconds(limits.idle_timeout);
    connections.push_back(std::move(c));
  }
}

void HttpServer::Impl::Loop() {
  std::vector<pollfd> fds;
  std::vector<std::list<Connection>::iterator> polled;
  struct Ready {
    std::list<Connection>::iterator c;
    ParseResult parsed;
    bool priority;
  };
  std::vector<Ready> ready;
  char chunk[4096];
  while (!stop.load()) {
    // Poll every socket until the nearest deadline (at most 100 ms).
    const auto now = Clock::now();
    auto nearest = now + std::chrono::milliseconds(100);
    fds.assign({{listen_fd, POLLIN, 0}, {wake_fd, POLLIN, 0}});
    polled.clear();
    for (auto it = connections.begin(); it != connections.end(); ++it) {
      fds.push_back({it->fd, static_cast<short>(it->writing ? POLLOUT : POLLIN), 0});
      polled.push_back(it);
      nearest = std::min(nearest, it->deadline);
    }
    const auto wait = std::chrono::duration_cast<std::chrono::milliseconds>(nearest - now);
    const int n = ::poll(fds.data(), fds.size(), static_cast<int>(std::max<long>(wait.count(), 0)));
    if (stop.load()) break;
    if (n < 0 && errno != EINTR) break;
    // Read and write what is ready; collect the requests that are now whole.
    ready.clear();
    std::vector<std::list<Connection>::iterator> dead;
    for (std::size_t i = 0; i < polled.size(); ++i) {
      Connection& c = *polled[i];
      const short ev = fds[i + 2].revents;
      if (ev == 0) continue;
      if (c.writing) {
        if ((ev & (POLLERR | POLLHUP | POLLNVAL)) != 0 || !Flush(c)) {
          dead.push_back(polled[i]);
        } else if (c.sent == c.out.size()) {
          c.writing = false;
          c.out.clear();
          if (c.close_after) {
            dead.push_back(polled[i]);
            continue;
          }
          // The next request: a pipelined one already begun has the request deadline.
          c.receiving = !c.in.empty();
          c.deadline = std::min(
              Clock::now() + Seconds(c.receiving ? limits.request_deadline : limits.idle_timeout),
              c.opened + Seconds(limits.connection_lifetime));
        }
        // A request that came with the last one (pipelined) is parsed below.
        if (c.writing || c.in.empty()) continue;
      } else {
        const ssize_t got = ::recv(c.fd, chunk, sizeof chunk, 0);
        if (got == 0 || (got < 0 && errno != EAGAIN && errno != EINTR)) {
          dead.push_back(polled[i]);
          continue;
        }
        if (got > 0) {
          if (!c.receiving) {
            c.receiving = true;
            c.deadline = std::min(Clock::now() + Seconds(limits.request_deadline),
                                  c.opened + Seconds(limits.connection_lifetime));
          }
          c.in.append(chunk, static_cast<std::size_t>(got));
        }
      }
      ParseResult parsed = ParseRequest(c.in, limits);
      if (parsed.status == ParseStatus::kIncomplete) continue;
      bool priority = false;
      if (parsed.status == ParseStatus::kComplete) {
        for (const RouteEntry& r : routes) {
          priority = priority || (r.priority && r.path == parsed.request.path);
        }
      }
      ready.push_back({polled[i], std::move(parsed), priority});
    }
    // The operator's requests first, then the viewers'.
    std::stable_partition(ready.begin(), ready.end(), [](const Ready& r) { return r.priority; });
    for (Ready& r : ready) {
      Connection& c = *r.c;
      if (r.parsed.status != ParseStatus::kComplete) {
        HttpResponse res;
        res.status = r.parsed.status == ParseStatus::kHeadTooLarge   ? 431
                     : r.parsed.status == ParseStatus::kBodyTooLarge ? 413
                     : r.parsed.status == ParseStatus::kUnsupported  ? 501
                                                                     : 400;
        res.body = r.parsed.why + "\n";
        Count(res.status == 400 || res.status == 501 ? &HttpCounters::malformed
                                                     : &HttpCounters::too_large);
        c.in.clear();
        Answer(c, res, false);
        continue;
      }
      c.in.erase(0, r.parsed.consumed);
      r.parsed.request.peer = c.peer;
      ++c.requests;
      HttpResponse res;
      try {
        res = Dispatch(r.parsed.request);
      } catch (const std::exception& e) {
        res.status = 500;
        res.body = std::string("internal error: ") + e.what() + "\n";
      }
      Count(&HttpCounters::served);
      const bool keep = r.parsed.keep_alive && c.requests < limits.max_requests &&
                        Clock::now() < c.opened + Seconds(limits.connection_lifetime);
      Answer(c, res, keep);
    }
    // Past a deadline: a request that is not whole gets 408; any other connection is closed.
    const auto later = Clock::now();
    for (auto it = connections.begin(); it != connections.end(); ++it) {
      if (it->deadline > later ||
          std::find(dead.begin(), dead.end(), it) != dead.end()) {
        continue;
      }
      if (!it->writing && it->receiving) {
        static constexpr std::string_view k408 =
            "HTTP/1.1 408 Request Timeout\r\nContent-Length: 0\r\nConnection: close\r\n\r\n";
        ::send(it->fd, k408.data(), k408.size(), MSG_NOSIGNAL | MSG_DONTWAIT);
      }
      Count(&HttpCounters::timed_out);
      dead.push_back(it);
    }
    for (auto it : dead) Close(it);
    // New connections last: making room may close one (the iterators above are done).
    if ((fds[0].revents & POLLIN) != 0) Accept();
  }
  for (auto it = connections.begin(); it != connections.end();) Close(it++);
}

HttpServer::HttpServer(const std::string& host, std::uint16_t port, HttpLimits limits)
    : impl_(std::make_unique<Impl>()) {
  impl_->limits = limits;
  addrinfo hints{};
  hints.ai_family = AF_UNSPEC;
  hints.ai_socktype = SOCK_STREAM;
  hints.ai_flags = AI_PASSIVE | AI_NUMERICSERV;
  addrinfo* found = nullptr;
  const std::string service = std::to_string(port);
  if (::getaddrinfo(host.c_str(), service.c_str(), &hints, &found) != 0 || found == nullptr) {
    throw TransferError(fmt::format("the monitor cannot listen on {}: not an address of this "
                                    "machine", host));
  }
  int fd = -1;
  for (addrinfo* a = found; a != nullptr && fd < 0; a = a->ai_next) {
    fd = ::socket(a->ai_family, a->ai_socktype | SOCK_NONBLOCK | SOCK_CLOEXEC, a->ai_protocol);
    if (fd < 0) continue;
    const int yes = 1;
    ::setsockopt(fd, SOL_SOCKET, SO_REUSEADDR, &yes, sizeof yes);
    if (::bind(fd, a->ai_addr, a->ai_addrlen) != 0 || ::listen(fd, 128) != 0) {
      ::close(fd);
      fd = -1;
    }
  }
  ::freeaddrinfo(found);
  if (fd < 0) {
    throw TransferError(fmt::format(
        "the monitor cannot listen on {}:{}: the port is in use or the address is not this "
        "machine's; choose another with --monitor HOST:PORT (port 0 picks a free one)",
        host, port));
  }
  sockaddr_storage bound{};
  socklen_t len = sizeof bound;
  ::getsockname(fd, reinterpret_cast<sockaddr*>(&bound), &len);
  port_ = ntohs(bound.ss_family == AF_INET6 ? reinterpret_cast<sockaddr_in6&>(bound).sin6_port
                                            : reinterpret_cast<sockaddr_in&>(bound).sin_port);
  impl_->listen_fd = fd;
  impl_->wake_fd = ::eventfd(0, EFD_NONBLOCK | EFD_CLOEXEC);
}

HttpServer::~HttpServer() {
  Stop();
  if (impl_->listen_fd >= 0) ::close(impl_->listen_fd);
  if (impl_->wake_fd >= 0) ::close(impl_->wake_fd);
}

void HttpServer::Route(const std::string& method, const std::string& path, HttpHandler handler,
                       bool priority) {
  impl_->routes.push_back({method, path, std::move(handler), priority});
}

void HttpServer::Start(std::function<void()> on_thread) {
  if (impl_->thread.joinable()) return;
  impl_->thread = std::thread([this, on_thread = std::move(on_thread)] {
    if (on_thread) on_thread();
    impl_->Loop();
  });
}

void HttpServer::Stop() {
  impl_->stop.store(true);
  const std::uint64_t one = 1;
  if (impl_->wake_fd >= 0) [[maybe_unused]] auto n = ::write(impl_->wake_fd, &one, sizeof one);
  if (impl_->thread.joinable()) impl_->thread.join();
}

HttpCounters HttpServer::counters() const {
  std::lock_guard lock(impl_->counters_mutex);
  return impl_->counters;
}

}  // namespace hybridtest::monitor
