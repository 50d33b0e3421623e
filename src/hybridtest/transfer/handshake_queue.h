#pragma once
// HandshakeQueue: the bench server's connections that are accepted but not yet authenticated.
//
// Why: a server that reads HELLO from one connection at a time with a blocking read can be
// stalled by anyone who opens a TCP connection and sends nothing (docs/protocol.md §3). Here
// every pending connection is read without blocking, as its bytes arrive, so a silent or slow
// peer never delays another one:
//  - each connection has `timeout` [s] from its accept to deliver one complete frame (HELLO);
//    after that it is dropped (TakeExpired);
//  - at most `capacity` connections wait at once; a new one beyond that evicts the oldest;
//  - the first frame may not exceed kMaxHandshakePayload bytes of payload (a HELLO is a
//    version, a token and a name), so a peer cannot make the server buffer 64 KiB per socket.
// The opening need not be a frame: a queue built with a Measure function reads whatever that
// function says the opening is (the OpenFresco server's token preamble and 44-byte header).
#include <atomic>
#include <chrono>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <span>
#include <string>
#include <vector>

#include "hybridtest/transfer/frame.h"
#include "hybridtest/transfer/socket.h"

namespace hybridtest::transfer {

inline constexpr std::uint32_t kMaxHandshakePayload = 4096;  // [bytes]

// The numeric address of the peer of a connected socket ("127.0.0.1", "::1"); "unknown" if it
// cannot be read.
std::string PeerAddress(int fd);

class HandshakeQueue {
 public:
  using Clock = std::chrono::steady_clock;
  struct Pending {
    Socket socket;
    std::string peer;                // PeerAddress()
    Clock::time_point deadline;      // accept time + timeout
    std::vector<std::uint8_t> bytes; // received so far (at most one frame)
  };
  enum class Progress { kWaiting, kFrame, kClosed };
  // Given the bytes of an opening received so far, the total number of bytes the opening has
  // (at least bytes.size() + 1 while more are needed; it may grow as the bytes tell more).
  // Throws TransferError for bytes that cannot begin a valid opening. It must bound the total.
  using Measure = std::function<std::size_t(std::span<const std::uint8_t> bytes)>;

  // `timeout` [s] > 0, `capacity` ≥ 1. Without `measure`, the opening is one frame (HELLO).
  HandshakeQueue(std::size_t capacity, double timeout, Measure measure = {});

  // Queues a just-accepted connection. Returns the peer of the connection evicted to make room,
  // or an empty string.
  std::string Add(Socket socket, Clock::time_point now);

  std::size_t size() const { return entries_.size(); }
  const Pending& at(std::size_t i) const { return entries_[i]; }

  // Reads, without blocking, what has arrived on entry i (at most up to the end of its first
  // frame). kFrame: `frame` holds the complete first frame. kClosed: the peer left. Throws
  // TransferError for bytes that are not a valid frame (or a payload above
  // kMaxHandshakePayload).
  Progress Read(std::size_t i, Frame& frame);
  // The same for any opening: kFrame when `bytes` holds the complete opening (as measured).
  // Throws what the Measure function throws.
  Progress ReadOpening(std::size_t i, std::vector<std::uint8_t>& bytes);

  // Removes and returns entry i / the expired entries / all entries.
  Pending Take(std::size_t i);
  std::vector<Pending> TakeExpired(Clock::time_point now);
  std::vector<Pending> TakeAll();

 private:
  std::size_t capacity_;
  Clock::duration timeout_;
  Measure measure_;
  std::vector<Pending> entries_;  // oldest first
};

// One turn of a server's accept loop, never blocked by one peer: waits up to `poll_ms` [ms]
// for a new connection on `listener` or bytes from a pending opening in `queue`; calls
// `advance(i)` for each opening with bytes, newest first, and ends the turn when it returns
// true (a session was served: the queue changed); calls `drop_expired()`; then, unless `stop`
// is set, queues a new connection, calling `on_evicted(address)` when the queue was full and
// its oldest opening was dropped.
void ServeOpeningsTurn(Listener& listener, HandshakeQueue& queue, int poll_ms,
                       const std::atomic<bool>& stop,
                       const std::function<bool(std::size_t)>& advance,
                       const std::function<void()>& drop_expired,
                       const std::function<void(const std::string&)>& on_evicted);

}  // namespace hybridtest::transfer
