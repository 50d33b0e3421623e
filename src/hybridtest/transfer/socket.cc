#include "hybridtest/transfer/socket.h"

#include <arpa/inet.h>
#include <fcntl.h>
#include <fmt/core.h>
#include <netdb.h>
#include <netinet/in.h>
#include <netinet/tcp.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <cmath>
#include <cstring>
#include <memory>

#include "hybridtest/common/error.h"

namespace hybridtest::transfer {

std::string PeerAddress(int fd) {
  sockaddr_storage address{};
  socklen_t length = sizeof(address);
  if (getpeername(fd, reinterpret_cast<sockaddr*>(&address), &length) != 0) return "unknown";
  char text[INET6_ADDRSTRLEN] = {};
  const void* raw = nullptr;
  if (address.ss_family == AF_INET) {
    raw = &reinterpret_cast<const sockaddr_in*>(&address)->sin_addr;
  } else if (address.ss_family == AF_INET6) {
    raw = &reinterpret_cast<const sockaddr_in6*>(&address)->sin6_addr;
  }
  if (raw == nullptr || inet_ntop(address.ss_family, raw, text, sizeof(text)) == nullptr) {
    return "unknown";
  }
  return text;
}
namespace {

using Clock = std::chrono::steady_clock;

struct AddrInfoDeleter {
  void operator()(addrinfo* p) const { freeaddrinfo(p); }
};
using AddrInfoPtr = std::unique_ptr<addrinfo, AddrInfoDeleter>;

AddrInfoPtr Resolve(const std::string& host, std::uint16_t port, bool passive) {
  addrinfo hints{};
  hints.ai_family = AF_UNSPEC;
  hints.ai_socktype = SOCK_STREAM;
  hints.ai_flags = AI_NUMERICSERV | (passive ? AI_PASSIVE : 0);
  addrinfo* result = nullptr;
  const std::string service = std::to_string(port);
  const int rc = getaddrinfo(host.c_str(), service.c_str(), &hints, &result);
  if (rc != 0) {
    throw ConfigError(fmt::format("cannot resolve host '{}': {}; give an IP address such as "
                                  "127.0.0.1 or a resolvable name",
                                  host, gai_strerror(rc)));
  }
  return AddrInfoPtr(result);
}

// Remaining milliseconds until `deadline`, for poll(); 0 when past.
int RemainingMs(Clock::time_point deadline) {
  const auto left =
      std::chrono::duration_cast<std::chrono::milliseconds>(deadline - Clock::now()).count();
  return left <= 0 ? 0 : static_cast<int>(std::min<long long>(left, 1 << 30));
}

Clock::time_point DeadlineAfter(double seconds) {
  return Clock::now() + std::chrono::microseconds(static_cast<long long>(
                            std::llround(std::max(seconds, 0.0) * 1e6)));
}

void SetNoDelay(int fd) {
  int one = 1;
  setsockopt(fd, IPPROTO_TCP, TCP_NODELAY, &one, sizeof one);
}

// Reads exactly n bytes before `deadline`. Returns kFrame on success.
ReadStatus ReadExactly(int fd, std::uint8_t* out, std::size_t n, Clock::time_point deadline) {
  std::size_t got = 0;
  while (got < n) {
    pollfd pfd{fd, POLLIN, 0};
    const int ready = poll(&pfd, 1, RemainingMs(deadline));
    if (ready < 0) {
      if (errno == EINTR) continue;
      return ReadStatus::kClosed;
    }
    if (ready == 0) return ReadStatus::kTimeout;
    const ssize_t r = recv(fd, out + got, n - got, 0);
    if (r == 0) return ReadStatus::kClosed;
    if (r < 0) {
      if (errno == EINTR || errno == EAGAIN || errno == EWOULDBLOCK) continue;
      return ReadStatus::kClosed;
    }
    got += static_cast<std::size_t>(r);
  }
  return ReadStatus::kFrame;
}

}  // namespace

Socket& Socket::operator=(Socket&& other) noexcept {
  if (this != &other) {
    Close();
    fd_ = other.fd_;
    other.fd_ = -1;
  }
  return *this;
}

void Socket::Close() noexcept {
  if (fd_ >= 0) {
    ::close(fd_);
    fd_ = -1;
  }
}

HostPort ParseHostPort(const std::string& text, const std::string& where) {
  const auto fail = [&](const std::string& why) {
    return ConfigError(fmt::format(
        "{} = '{}': {}; expected HOST:PORT such as 127.0.0.1:7471 ([::1]:7471 for IPv6, "
        "port 0 to pick a free port)",
        where, text, why));
  };
  const auto colon = text.rfind(':');
  if (colon == std::string::npos) throw fail("no ':' before the port");
  HostPort hp;
  hp.host = text.substr(0, colon);
  if (hp.host.size() >= 2 && hp.host.front() == '[' && hp.host.back() == ']') {
    hp.host = hp.host.substr(1, hp.host.size() - 2);
  }
  if (hp.host.empty()) throw fail("empty host");
  const std::string port_text = text.substr(colon + 1);
  if (port_text.empty() || port_text.size() > 5 ||
      port_text.find_first_not_of("0123456789") != std::string::npos) {
    throw fail("the port is not a number");
  }
  const long port = std::stol(port_text);
  if (port > 65535) throw fail("the port is above 65535");
  hp.port = static_cast<std::uint16_t>(port);
  return hp;
}

bool IsLoopbackHost(const std::string& host) {
  const AddrInfoPtr list = Resolve(host, 0, false);
  for (const addrinfo* ai = list.get(); ai != nullptr; ai = ai->ai_next) {
    if (ai->ai_family == AF_INET) {
      const auto* sin = reinterpret_cast<const sockaddr_in*>(ai->ai_addr);
      if ((ntohl(sin->sin_addr.s_addr) >> 24) != 127) return false;
    } else if (ai->ai_family == AF_INET6) {
      const auto* sin6 = reinterpret_cast<const sockaddr_in6*>(ai->ai_addr);
      if (!IN6_IS_ADDR_LOOPBACK(&sin6->sin6_addr)) return false;
    } else {
      return false;
    }
  }
  return true;
}

Socket ConnectTcp(const std::string& host, std::uint16_t port, double timeout) {
  const auto deadline = DeadlineAfter(timeout);
  AddrInfoPtr list;
  try {
    list = Resolve(host, port, false);
  } catch (const ConfigError& e) {
    throw TransferError(fmt::format("cannot connect to {}:{}: {}", host, port,
                                    e.what()));
  }
  std::string last_error = "no address";
  for (const addrinfo* ai = list.get(); ai != nullptr; ai = ai->ai_next) {
    Socket s(::socket(ai->ai_family, ai->ai_socktype | SOCK_CLOEXEC, ai->ai_protocol));
    if (!s.is_open()) {
      last_error = std::strerror(errno);
      continue;
    }
    // Non-blocking connect, bounded by poll, then back to blocking mode.
    const int flags = fcntl(s.fd(), F_GETFL, 0);
    fcntl(s.fd(), F_SETFL, flags | O_NONBLOCK);
    int rc = ::connect(s.fd(), ai->ai_addr, ai->ai_addrlen);
    if (rc != 0 && errno == EINPROGRESS) {
      pollfd pfd{s.fd(), POLLOUT, 0};
      do {
        rc = poll(&pfd, 1, RemainingMs(deadline));
      } while (rc < 0 && errno == EINTR);
      if (rc == 0) {
        last_error = fmt::format("no answer within {} s", timeout);
        continue;
      }
      int err = 0;
      socklen_t len = sizeof err;
      getsockopt(s.fd(), SOL_SOCKET, SO_ERROR, &err, &len);
      rc = err == 0 ? 0 : -1;
      errno = err;
    }
    if (rc != 0) {
      last_error = std::strerror(errno);
      continue;
    }
    fcntl(s.fd(), F_SETFL, flags);
    SetNoDelay(s.fd());
    return s;
  }
  throw TransferError(fmt::format("cannot connect to {}:{}: {}", host, port, last_error));
}

Listener::Listener(const std::string& host, std::uint16_t port) : host_(host) {
  AddrInfoPtr list = Resolve(host, port, true);
  std::string last_error = "no address";
  for (const addrinfo* ai = list.get(); ai != nullptr; ai = ai->ai_next) {
    Socket s(::socket(ai->ai_family, ai->ai_socktype | SOCK_CLOEXEC, ai->ai_protocol));
    if (!s.is_open()) {
      last_error = std::strerror(errno);
      continue;
    }
    int one = 1;
    setsockopt(s.fd(), SOL_SOCKET, SO_REUSEADDR, &one, sizeof one);
    if (::bind(s.fd(), ai->ai_addr, ai->ai_addrlen) != 0 || ::listen(s.fd(), 4) != 0) {
      last_error = std::strerror(errno);
      continue;
    }
    sockaddr_storage bound{};
    socklen_t len = sizeof bound;
    getsockname(s.fd(), reinterpret_cast<sockaddr*>(&bound), &len);
    port_ = ntohs(bound.ss_family == AF_INET6
                      ? reinterpret_cast<sockaddr_in6*>(&bound)->sin6_port
                      : reinterpret_cast<sockaddr_in*>(&bound)->sin_port);
    socket_ = std::move(s);
    return;
  }
  throw TransferError(fmt::format(
      "cannot listen on {}:{}: {}; choose another port (or 0 for any free port)", host, port,
      last_error));
}

std::string Listener::address() const {
  return host_.find(':') != std::string::npos ? fmt::format("[{}]:{}", host_, port_)
                                              : fmt::format("{}:{}", host_, port_);
}

Socket Listener::Accept(double timeout) {
  pollfd pfd{socket_.fd(), POLLIN, 0};
  const int ready = poll(&pfd, 1, static_cast<int>(std::lround(timeout * 1e3)));
  if (ready <= 0) return Socket();
  Socket s(::accept4(socket_.fd(), nullptr, nullptr, SOCK_CLOEXEC));
  if (s.is_open()) SetNoDelay(s.fd());
  return s;
}

bool SendAll(int fd, const std::vector<std::uint8_t>& bytes, double timeout) {
  const auto deadline = DeadlineAfter(timeout);
  std::size_t sent = 0;
  while (sent < bytes.size()) {
    pollfd pfd{fd, POLLOUT, 0};
    const int ready = poll(&pfd, 1, RemainingMs(deadline));
    if (ready < 0 && errno == EINTR) continue;
    if (ready <= 0) return false;
    const ssize_t w = ::send(fd, bytes.data() + sent, bytes.size() - sent, MSG_NOSIGNAL);
    if (w < 0) {
      if (errno == EINTR || errno == EAGAIN || errno == EWOULDBLOCK) continue;
      return false;
    }
    sent += static_cast<std::size_t>(w);
  }
  return true;
}

ReadStatus ReadBytes(int fd, double timeout, std::vector<std::uint8_t>& out) {
  return ReadExactly(fd, out.data(), out.size(), DeadlineAfter(timeout));
}

ReadStatus ReadFrame(int fd, double timeout, Frame& out) {
  const auto deadline = DeadlineAfter(timeout);
  std::vector<std::uint8_t> bytes(kFrameHeaderSize);
  ReadStatus status = ReadExactly(fd, bytes.data(), kFrameHeaderSize, deadline);
  if (status != ReadStatus::kFrame) return status;
  const FrameHeader header = DecodeFrameHeader(bytes);
  bytes.resize(kFrameHeaderSize + header.payload_length + kFrameTrailerSize);
  status = ReadExactly(fd, bytes.data() + kFrameHeaderSize, bytes.size() - kFrameHeaderSize,
                       deadline);
  if (status != ReadStatus::kFrame) return status;
  out = DecodeFrame(bytes);
  return ReadStatus::kFrame;
}

}  // namespace hybridtest::transfer
