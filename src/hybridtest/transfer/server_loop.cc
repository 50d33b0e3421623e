// See server_loop.h.
#include "hybridtest/transfer/server_loop.h"

#include <fmt/core.h>
#include <netinet/in.h>
#include <netinet/tcp.h>
#include <poll.h>
#include <sys/socket.h>

#include <algorithm>
#include <cerrno>

#include "hybridtest/common/error.h"

namespace hybridtest::transfer {
namespace {

using Seconds = std::chrono::duration<double>;

const ServerLoopLimits& Checked(const ServerLoopLimits& l) {
  if (l.max_connections < 1 || l.max_frame_bytes < 1 || !(l.handshake_timeout > 0.0) ||
      !(l.frame_timeout > 0.0) || !(l.idle_timeout > 0.0) || !(l.send_timeout > 0.0) ||
      l.poll_ms < 1) {
    throw ConfigError(fmt::format(
        "server limits: max_connections = {}, max_frame_bytes = {}, handshake_timeout = {} s, "
        "frame_timeout = {} s, idle_timeout = {} s, send_timeout = {} s, poll interval = {} ms: "
        "expected all positive",
        l.max_connections, l.max_frame_bytes, l.handshake_timeout, l.frame_timeout,
        l.idle_timeout, l.send_timeout, l.poll_ms));
  }
  return l;
}

ServerLoopLimits WithOpeningBound(ServerLoopLimits l) {
  if (l.max_opening_bytes == 0 || l.max_opening_bytes > l.max_frame_bytes) {
    l.max_opening_bytes = l.max_frame_bytes;
  }
  return l;
}

}  // namespace

ServerLoop::ServerLoop(Listener& listener, ServerLoopLimits limits, Measure measure,
                       Handler handler, std::function<void(const std::string&)> log)
    : listener_(listener),
      limits_(WithOpeningBound(Checked(limits))),
      measure_(std::move(measure)),
      handler_(std::move(handler)),
      log_(std::move(log)) {}

void ServerLoop::Log(const std::string& line) const {
  if (log_) log_(line);
}

void ServerLoop::Serve(const std::atomic<bool>& stop, const std::function<void()>& after_turn) {
  while (!stop.load()) {
    Turn();
    if (after_turn) after_turn();
  }
  CloseAll("the server stops");
}

void ServerLoop::CloseAll(const std::string& why) {
  for (Connection& c : connections_) Close(c, CloseCause::kStopping, why);
  connections_.clear();
}

void ServerLoop::CloseWaiting(int except, const std::string& why) {
  for (Connection& c : connections_) {
    if (!c.established && c.id != except) Close(c, CloseCause::kByHandler, why);
  }
}

bool ServerLoop::Send(Connection& c, const std::vector<std::uint8_t>& bytes) const {
  return c.socket.is_open() && SendAll(c.socket.fd(), bytes, limits_.send_timeout);
}

bool ServerLoop::Claim(int id) {
  if (commander_ == 0) commander_ = id;
  return commander_ == id;
}

void ServerLoop::Release(int id) {
  if (commander_ == id) commander_ = 0;
}

void ServerLoop::Close(Connection& c, CloseCause cause, const std::string& why) {
  if (!c.socket.is_open()) return;
  Closing closing;
  closing.cause = cause;
  closing.why = why;
  closing.commander = c.id == commander_;
  if (closing.commander) commander_ = 0;
  closing.another_commands = commander_ != 0;
  if (handler_.closed) handler_.closed(c, closing);
  c.socket.Close();
}

bool ServerLoop::Evict(const std::string& why) {
  // Waiting for its opening first (oldest accept), else the longest-silent reader.
  Connection* victim = nullptr;
  const auto before = [](const Connection& a, const Connection& b) {
    if (a.established != b.established) return !a.established;
    return a.established ? a.last_seen < b.last_seen : a.accepted < b.accepted;
  };
  for (Connection& c : connections_) {
    if (!c.socket.is_open() || c.id == commander_) continue;
    if (victim == nullptr || before(c, *victim)) victim = &c;
  }
  if (victim == nullptr) return false;
  Close(*victim, CloseCause::kMakeRoom, why);
  return true;
}

void ServerLoop::Turn() {
  ++turns_;
  const auto now0 = Clock::now();
  const bool listen = now0 >= accept_paused_until_;
  std::vector<pollfd> fds;
  fds.push_back({listen ? listener_.fd() : -1, POLLIN, 0});
  for (const Connection& c : connections_) fds.push_back({c.socket.fd(), POLLIN, 0});
  if (::poll(fds.data(), fds.size(), limits_.poll_ms) < 0 && errno != EINTR) {
    throw TransferError(fmt::format("server loop: poll failed (errno {})", errno));
  }
  const auto now = Clock::now();
  // Connections first (the index of fds follows connections_ until Accept appends).
  for (std::size_t i = 1; i < fds.size(); ++i) {
    Connection& c = connections_[i - 1];
    if (fds[i].revents != 0 && c.socket.is_open()) Read(c, now);
    if (!c.socket.is_open()) continue;
    if (!c.established && Seconds(now - c.accepted).count() > limits_.handshake_timeout) {
      Close(c, CloseCause::kHandshakeTimeout,
            fmt::format("no complete opening within {} s of connecting ({} bytes arrived; "
                        "handshake timeout)", limits_.handshake_timeout, c.buffer.size()));
    } else if (!c.buffer.empty() &&
               Seconds(now - c.frame_started).count() > limits_.frame_timeout) {
      Close(c, CloseCause::kFrameTimeout,
            fmt::format("incomplete frame: {} bytes arrived, the rest not within {} s of the "
                        "first (frame timeout)", c.buffer.size(), limits_.frame_timeout));
    } else if (Seconds(now - c.last_seen).count() > limits_.idle_timeout) {
      Close(c, CloseCause::kIdleTimeout,
            fmt::format("silent for {} s (idle timeout)", limits_.idle_timeout));
    }
  }
  std::erase_if(connections_, [](const Connection& c) { return !c.socket.is_open(); });
  if (listen && (fds[0].revents & POLLIN)) Accept(now);
}

void ServerLoop::Accept(Clock::time_point now) {
  int fd = ::accept4(listener_.fd(), nullptr, nullptr, SOCK_CLOEXEC | SOCK_NONBLOCK);
  if (fd < 0 && (errno == EMFILE || errno == ENFILE)) {
    // The file limit: make room (Evict), else leave the listener
    // alone for one poll interval (polling it again at once would spin).
    if (Evict("closed to make room: the server is at its file limit (EMFILE)")) {
      fd = ::accept4(listener_.fd(), nullptr, nullptr, SOCK_CLOEXEC | SOCK_NONBLOCK);
    }
    if (fd < 0) {
      accept_paused_until_ = now + std::chrono::milliseconds(limits_.poll_ms);
      ++refused_;
      Log("a connection waits: the server is at its file limit (EMFILE) and every connection "
          "is busy");
      return;
    }
  }
  if (fd < 0) return;  // the peer left before the accept, or EINTR: nothing to do
  Socket s(fd);
  const int one = 1;
  ::setsockopt(fd, IPPROTO_TCP, TCP_NODELAY, &one, sizeof one);
  std::erase_if(connections_, [](const Connection& c) { return !c.socket.is_open(); });
  if (connections_.size() >= limits_.max_connections &&
      !Evict(fmt::format("closed to make room: {} connections at once (the bound); this one "
                         "waited longest", limits_.max_connections))) {
    ++refused_;
    Log(fmt::format("refused a connection from {}: {} connections at once (the bound)",
                    PeerAddress(fd), limits_.max_connections));
    return;
  }
  std::erase_if(connections_, [](const Connection& c) { return !c.socket.is_open(); });
  Connection c;
  c.socket = std::move(s);
  c.id = next_id_++;
  c.peer = PeerAddress(fd);
  c.accepted = now;
  c.last_seen = now;
  connections_.push_back(std::move(c));
  Connection& added = connections_.back();
  if (handler_.opened && !handler_.opened(added)) {
    ++refused_;
    Close(added, CloseCause::kRefused, "refused when it opened");
  }
}

void ServerLoop::Read(Connection& c, Clock::time_point now) {
  // At most up to the bound: the buffer never holds more than max_frame_bytes.
  std::uint8_t chunk[4096];
  const std::size_t bound = c.established ? limits_.max_frame_bytes : limits_.max_opening_bytes;
  const std::size_t room = bound - std::min(bound, c.buffer.size());
  if (room == 0) {
    return Close(c, CloseCause::kTooLong,
                 fmt::format("{} bytes buffered without a complete frame (the bound)", bound));
  }
  const ssize_t got = ::recv(c.socket.fd(), chunk, std::min(room, sizeof chunk), 0);
  if (got == 0) return Close(c, CloseCause::kPeerLeft, "connection closed by the client");
  if (got < 0) {
    if (errno == EAGAIN || errno == EWOULDBLOCK || errno == EINTR) return;
    return Close(c, CloseCause::kPeerLeft, "connection reset by the client");
  }
  if (c.buffer.empty()) c.frame_started = now;
  c.last_seen = now;
  c.buffer.insert(c.buffer.end(), chunk, chunk + got);
  while (!c.buffer.empty() && c.socket.is_open()) {
    std::size_t size = 0;
    try {
      size = measure_(c, c.buffer);
    } catch (const TransferError& e) {
      return Close(c, CloseCause::kGarbled, e.what());
    }
    const std::size_t most = c.established ? limits_.max_frame_bytes : limits_.max_opening_bytes;
    if (size > most) {
      return Close(c, CloseCause::kTooLong,
                   fmt::format("a {} of {} bytes: longer than the {} bytes it may have",
                               c.established ? "frame" : "opening", size, most));
    }
    if (c.buffer.size() < size) return;  // the rest has not arrived yet
    const std::vector<std::uint8_t> frame(c.buffer.begin(),
                                          c.buffer.begin() + static_cast<std::ptrdiff_t>(size));
    c.buffer.erase(c.buffer.begin(), c.buffer.begin() + static_cast<std::ptrdiff_t>(size));
    c.frame_started = now;
    if (!handler_.frame(c, frame)) return Close(c, CloseCause::kByHandler, "closed by the server");
  }
}

}  // namespace hybridtest::transfer
