#pragma once
// ServerLoop: the one connection loop of every server of the project — the bench protocol
// (BenchServer), OpenFresco (openfresco::Server) and the ADS PLC emulator (AdsServer). A
// protocol supplies only its codec (Measure: where the frame begun ends) and its handler
// (what to do with a complete frame); the limits below are the loop's and hold for every
// protocol on it (docs/safety.md "Server limits").
//
// Guarantees, all enforced here:
//  - One thread, poll(2), every socket non-blocking: bytes are read as they arrive, so a client
//    that drips, stops mid-frame or idles never delays another.
//  - A connection must complete its opening (the protocol marks it `established`: a HELLO, an
//    OpenFresco header) within `handshake_timeout` [s] of its accept, and its opening may not
//    exceed `max_opening_bytes` (so an unauthenticated peer cannot make the server buffer a
//    full frame), else it is closed.
//  - A frame that has begun must be complete within `frame_timeout` [s] of its first byte, else
//    its connection is closed ("incomplete frame"); dripping bytes does not extend it.
//  - An established connection that sends nothing for `idle_timeout` [s] is closed.
//  - A frame longer than `max_frame_bytes` is refused before it is buffered (the connection is
//    closed), so a connection never holds more than max_frame_bytes of input.
//  - At most `max_connections` connections at once. One more (or an accept refused by the
//    process's file limit, EMFILE/ENFILE) closes the longest-waiting connection that has not
//    completed its opening, else the longest-silent one that is not the commander, to make
//    room; when none can be closed, the new connection is refused (closed at once) or, at the
//    file limit, the listener is left alone for one poll interval — the loop never spins on a
//    listener it cannot accept from.
//  - One commander at a time: Claim(id) makes connection `id` the commander if nobody is;
//    another connection's Claim fails until the commander's connection ends or it Release()s.
//    Any connection may read. The handler decides which requests need the claim.
//  - Every end of a connection is reported to the handler once (Handler::closed) with its
//    cause, before the socket is closed, so the protocol can answer (an error, BYE) and hold.
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
  std::size_t max_opening_bytes = 0;     // longest opening; 0: max_frame_bytes. Unit: [bytes].
  double handshake_timeout = 2.0;        // the opening must be complete within. Unit: [s].
  double frame_timeout = 2.0;            // a begun frame must be complete within. Unit: [s].
  double idle_timeout = 30.0;            // a connection silent this long is closed. Unit: [s].
  double send_timeout = 2.0;             // longest wait to write one answer. Unit: [s].
  int poll_ms = 100;                     // one turn's longest wait. Unit: [ms].
};

// Why a connection ends (Handler::closed).
enum class CloseCause {
  kPeerLeft,          // the client closed or reset its end
  kHandshakeTimeout,  // no complete opening within handshake_timeout
  kFrameTimeout,      // a begun frame not complete within frame_timeout
  kIdleTimeout,       // silent for idle_timeout
  kGarbled,           // bytes that cannot begin a frame (the codec threw)
  kTooLong,           // a frame (or opening) beyond its bound
  kMakeRoom,          // closed to make room for a new connection
  kRefused,           // the handler refused it when it opened, or max_connections is reached
  kByHandler,         // the handler asked (its frame handler returned false, or Close())
  kStopping,          // the server stops
};

class ServerLoop {
 public:
  using Clock = std::chrono::steady_clock;
  struct Connection {
    Socket socket;
    int id = 0;                        // 1, 2, ... in accept order
    std::string peer;                  // numeric address of the client ("127.0.0.1")
    bool established = false;          // set by the handler once the opening is accepted
    std::vector<std::uint8_t> buffer;  // bytes of the frame begun (≤ max_frame_bytes)
    Clock::time_point accepted;        // the accept
    Clock::time_point last_seen;       // the last byte received (or the accept)
    Clock::time_point frame_started;   // first byte of the frame in `buffer`
  };
  // The codec: given the bytes of the frame begun on `c` (non-empty), the total size of that
  // frame (more than bytes.size() while bytes are missing; it may grow as the bytes tell more).
  // Throws TransferError for bytes that cannot begin a frame (the connection is closed).
  using Measure =
      std::function<std::size_t(const Connection& c, std::span<const std::uint8_t> bytes)>;
  struct Closing {
    CloseCause cause = CloseCause::kPeerLeft;
    std::string why;       // for the log: what happened, with the limit
    bool commander = false;        // the connection held the claim (now released)
    bool another_commands = false; // another connection holds the claim
  };
  struct Handler {
    // A new connection; returns false to refuse it (it is closed at once). May be empty.
    std::function<bool(Connection&)> opened;
    // One complete frame; returns false when the connection must be closed (after any answer
    // it sent with Send()).
    std::function<bool(Connection&, std::span<const std::uint8_t> frame)> frame;
    // The connection ends: called once, before its socket is closed (a last Send() is possible
    // unless the peer left). May be empty.
    std::function<void(Connection&, const Closing&)> closed;
  };

  // `listener` must outlive the loop. Throws ConfigError for limits that are not positive.
  ServerLoop(Listener& listener, ServerLoopLimits limits, Measure measure, Handler handler,
             std::function<void(const std::string&)> log = {});

  // Serves until `stop` is set (checked at least every poll_ms), then closes every connection.
  // `after_turn`, if given, runs after every turn (a protocol's own deadlines: a watchdog).
  void Serve(const std::atomic<bool>& stop, const std::function<void()>& after_turn = {});
  // One turn: waits up to poll_ms, accepts, reads, hands complete frames, applies deadlines.
  void Turn();
  void CloseAll(const std::string& why);
  // Closes every connection that has not completed its opening, but `except` (an id).
  void CloseWaiting(int except, const std::string& why);

  // Writes `bytes` to `c` within send_timeout; false (the caller closes) if it could not.
  bool Send(Connection& c, const std::vector<std::uint8_t>& bytes) const;

  bool Claim(int id);          // true if `id` is (now) the commander
  void Release(int id);        // `id` gives up the claim (no effect if it does not hold it)
  int commander() const { return commander_; }  // 0: nobody
  std::size_t connections() const { return connections_.size(); }
  long refused_connections() const { return refused_; }  // lifetime count
  // Turns taken (poll wake-ups), lifetime; readable from any thread. An idle server takes
  // about one per poll_ms: a flood at the file limit must not make it spin.
  long turns() const { return turns_.load(); }

 private:
  void Accept(Clock::time_point now);
  void Read(Connection& c, Clock::time_point now);
  void Close(Connection& c, CloseCause cause, const std::string& why);
  // Closes the connection waiting longest for its opening, else the longest-silent one that
  // is not the commander; false if there is none.
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
  std::atomic<long> turns_{0};
  Clock::time_point accept_paused_until_{};
};

}  // namespace hybridtest::transfer
