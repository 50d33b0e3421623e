// See handshake_queue.h.
#include "hybridtest/transfer/handshake_queue.h"

#include <arpa/inet.h>
#include <fmt/core.h>
#include <netinet/in.h>
#include <poll.h>
#include <sys/socket.h>

#include <cerrno>
#include <cmath>

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

// The opening of the bench protocol: one frame, its payload at most kMaxHandshakePayload.
std::size_t MeasureFrame(std::span<const std::uint8_t> bytes) {
  if (bytes.size() < kFrameHeaderSize) return kFrameHeaderSize;
  const FrameHeader header = DecodeFrameHeader(bytes.first(kFrameHeaderSize));
  if (header.payload_length > kMaxHandshakePayload) {
    throw TransferError(fmt::format("the first frame declares a payload of {} bytes; a HELLO "
                                    "has at most {}", header.payload_length,
                                    kMaxHandshakePayload));
  }
  return kFrameHeaderSize + header.payload_length + kFrameTrailerSize;
}

}  // namespace

HandshakeQueue::HandshakeQueue(std::size_t capacity, double timeout, Measure measure)
    : capacity_(capacity < 1 ? 1 : capacity),
      timeout_(std::chrono::duration_cast<Clock::duration>(
          std::chrono::duration<double>(timeout > 0.0 ? timeout : 1.0))),
      measure_(measure ? std::move(measure) : Measure(MeasureFrame)) {}

std::string HandshakeQueue::Add(Socket socket, Clock::time_point now) {
  std::string evicted;
  if (entries_.size() >= capacity_) {
    evicted = entries_.front().peer;
    entries_.erase(entries_.begin());
  }
  Pending p;
  p.peer = PeerAddress(socket.fd());
  p.socket = std::move(socket);
  p.deadline = now + timeout_;
  entries_.push_back(std::move(p));
  return evicted;
}

HandshakeQueue::Progress HandshakeQueue::Read(std::size_t i, Frame& frame) {
  std::vector<std::uint8_t> bytes;
  const Progress progress = ReadOpening(i, bytes);
  if (progress == Progress::kFrame) frame = DecodeFrame(bytes);
  return progress;
}

HandshakeQueue::Progress HandshakeQueue::ReadOpening(std::size_t i,
                                                     std::vector<std::uint8_t>& bytes) {
  Pending& p = entries_[i];
  // Read up to what the opening needs so far; the measure may grow as its bytes arrive.
  for (;;) {
    const std::size_t needed = measure_(p.bytes);
    if (p.bytes.size() >= needed) break;
    const std::size_t have = p.bytes.size();
    p.bytes.resize(needed);
    const ssize_t r = ::recv(p.socket.fd(), p.bytes.data() + have, needed - have, MSG_DONTWAIT);
    if (r <= 0) {
      p.bytes.resize(have);
      if (r == 0) return Progress::kClosed;
      return (errno == EAGAIN || errno == EWOULDBLOCK || errno == EINTR) ? Progress::kWaiting
                                                                        : Progress::kClosed;
    }
    p.bytes.resize(have + static_cast<std::size_t>(r));
    if (p.bytes.size() < needed) return Progress::kWaiting;
  }
  bytes = p.bytes;
  return Progress::kFrame;
}

HandshakeQueue::Pending HandshakeQueue::Take(std::size_t i) {
  Pending p = std::move(entries_[i]);
  entries_.erase(entries_.begin() + static_cast<std::ptrdiff_t>(i));
  return p;
}

std::vector<HandshakeQueue::Pending> HandshakeQueue::TakeExpired(Clock::time_point now) {
  std::vector<Pending> expired;
  for (std::size_t i = entries_.size(); i-- > 0;) {
    if (now >= entries_[i].deadline) expired.push_back(Take(i));
  }
  return expired;
}

std::vector<HandshakeQueue::Pending> HandshakeQueue::TakeAll() {
  std::vector<Pending> all = std::move(entries_);
  entries_.clear();
  return all;
}

void ServeOpeningsTurn(Listener& listener, HandshakeQueue& queue, int poll_ms,
                       const std::atomic<bool>& stop,
                       const std::function<bool(std::size_t)>& advance,
                       const std::function<void()>& drop_expired,
                       const std::function<void(const std::string&)>& on_evicted) {
  std::vector<pollfd> fds = {{listener.fd(), POLLIN, 0}};
  for (std::size_t i = 0; i < queue.size(); ++i) fds.push_back({queue.at(i).socket.fd(), POLLIN, 0});
  poll(fds.data(), fds.size(), poll_ms);
  // Pending openings, last first so that removing one keeps the others' indices.
  for (std::size_t k = fds.size(); k-- > 1;) {
    if ((fds[k].revents & (POLLIN | POLLHUP | POLLERR)) != 0 && advance(k - 1)) break;
  }
  drop_expired();
  if ((fds[0].revents & POLLIN) != 0 && !stop.load()) {
    Socket client = listener.Accept(0.0);
    if (client.is_open()) {
      const std::string evicted = queue.Add(std::move(client), HandshakeQueue::Clock::now());
      if (!evicted.empty()) on_evicted(evicted);
    }
  }
}

}  // namespace hybridtest::transfer
