#pragma once
// ServerLoop: the one connection loop of the servers that serve several clients at once (the
// ADS PLC emulator; docs/ads.md "Server limits"). A protocol supplies only its codec (Measure:
// where its first frame ends) and its handler (what to do with a complete frame); the limits
// below are the loop's and hold for every protocol on it.
//
// Guarantees, all enforced here:
//  - One thread, poll(2), every socket non-blocking: bytes are read as they arrive, so a client
//    that drips, stops mid-frame or idles never delays another.
//  - A frame that has begun must be complete within `frame_timeout` [s] of its first byte, else
//    its connection is closed ("incomplete frame"); dripping bytes does not extend it.
//  - A connection that sends nothing for `idle_timeout` [s] is closed.
//  - A frame longer than `max_frame_bytes` is refused before it is buffered (the connection is
//    closed), so a connection never holds more than max_frame_bytes of input.
//  - At most `max_connections` connections at once. One more (or an accept refused by the
//    process's file limit, EMFILE/ENFILE) closes the longest-silent connection that is not the
//    commander to make room; when none can be closed, the new connection is refused (closed at
//    once) or, at the file limit, the listener is left alone for one poll interval — the loop
//    never spins on a listener it cannot accept from.
//  - One commander at a time: Claim(id) makes connection `id` the commander if nobody is;
//    another connection's Claim fails until the commander's connection ends or it Release()s.
//    Any connection may read. The handler decides which requests need the claim.
#include <atomic>
#include <chrono>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <span>
#include <string>
#include <vector>

#include "hybridtest/transfer/socket.h"

namespace hybridtest::transfer {

struct ServerLoopLimits {
  std::size_t max_connections = 16;      // connections at once (≥ 1)
  std::size_t max_frame_bytes = 1 << 16; // longest frame accepted. Unit: [bytes].
  double frame_timeout = 2.0;            // a begun frame must be complete within. Unit: [s].
  double idle_timeout = 30.0;            // a connection silent this long is closed. Unit: [s].
  double send_timeout = 2.0;             // longest wait to write one answer. Unit: [s].
  int poll_ms = 100;                     // one turn's longest wait. Unit: [ms].
};

class ServerLoop {
 public:
  using Clock = std::chrono::steady_clock;
  struct Connection {
    Socket socket;
    int id = 0;                        // 1, 2, ... in accept order
    std::string peer;                  // numeric address of the client ("127.0.0.1")
    std::vector<std::uint8_t> buffer;  // bytes of the frame begun (≤ max_frame_bytes)
    Clock::time_point last_seen;       // the last byte received (or the accept)
    Clock::time_point frame_started;   // first byte of the frame in `buffer`
  };
  // The codec: given the bytes of the frame begun (non-empty), the total size of that frame
  // (more than bytes.size() while bytes are missing; it may grow as the bytes tell more).
  // Throws TransferError for bytes that cannot begin a frame (the connection is closed).
  using Measure = std::function<std::size_t(std::span<const std::uint8_t> bytes)>;
  struct Handler {
    std::function<void(Connection&)> opened;  // may be empty
    // One complete frame; returns false when the connection must be closed (after any answer
    // it sent with Send()).
    std::function<bool(Connection&, std::span<const std::uint8_t> frame)> frame;
    // The connection is closed; `commander` if it held the claim (now released). May be empty.
    std::function<void(const Connection&, const std::string& why, bool commander)> closed;
  };

  // `listener` must outlive the loop. Throws ConfigError for limits that are not positive.
  ServerLoop(Listener& listener, ServerLoopLimits limits, Measure measure, Handler handler,
             std::function<void(const std::string&)> log = {});

  // Serves until `stop` is set (checked at least every poll_ms), then closes every connection.
  void Serve(const std::atomic<bool>& stop);
  // One turn: waits up to poll_ms, accepts, reads, hands complete frames, applies deadlines.
  void Turn();
  void CloseAll(const std::string& why);

  // Writes `bytes` to `c` within send_timeout; false (the caller closes) if it could not.
  bool Send(Connection& c, const std::vector<std::uint8_t>& bytes) const;

  bool Claim(int id);          // true if `id` is (now) the commander
  void Release(int id);        // `id` gives up the claim (no effect if it does not hold it)
  int commander() const { return commander_; }  // 0: nobody
  std::size_t connections() const { return connections_.size(); }
  long refused_connections() const { return refused_; }  // lifetime count

 private:
  void Accept(Clock::time_point now);
  void Read(Connection& c, Clock::time_point now);
  void Close(Connection& c, const std::string& why);
  // Closes the longest-silent connection that is not the commander; false if there is none.
  bool Evict(const std::string& why);
  void Log(const std::string& line) const;

  Listener& listener_;
  ServerLoopLimits limits_;
  Measure measure_;
  Handler handler_;
  std::function<void(const std::string&)> log_;
  std::vector<Connection> connections_;
  int next_id_ = 1;
  int commander_ = 0;
  long refused_ = 0;
  Clock::time_point accept_paused_until_{};
};

}  // namespace hybridtest::transfer
