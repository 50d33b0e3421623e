#pragma once
// BenchServer: serves one TransferSystem over TCP with the hybridtest bench protocol v1
// (docs/protocol.md): one client commands, others may read.
//
// Safety rules, in the order they are applied:
//  - It binds 127.0.0.1 by default and refuses to bind any non-loopback address unless a
//    shared token of at least 16 bytes (not only whitespace) is configured; with a token, a
//    HELLO carrying another token is refused (compared in constant time; five wrong tokens
//    from one address block — IPv4 /24, IPv6 /64 — lock that block out for a minute, logged,
//    and a global budget bounds wrong tokens from all addresses together; see auth.h).
//  - Connections are served by the shared ServerLoop (server_loop.h) with its limits: every
//    accepted connection has handshake_timeout to deliver its HELLO (of at most
//    kMaxHelloPayload bytes of payload), read without blocking, so an idle, slow or dripping
//    peer never delays a real client; a begun frame must be complete within heartbeat_timeout;
//    at most max_connections at once (one more closes the connection that waited longest for
//    its HELLO, else the longest-silent reader); the process's file limit never makes it spin.
//  - One client commands: the first session to send a COMMAND (or HOLD) holds the bench until
//    its connection ends; meanwhile another session's COMMAND or HOLD is answered ERROR(BUSY)
//    and changes nothing (its session goes on), while READ and HEARTBEAT are served to every
//    session. A session in progress is never taken over.
//  - Every request of a session must carry the sequence number after the previous one's
//    (HELLO's + 1, + 2, ...). A duplicate, stale or skipped number (a replayed COMMAND) is
//    refused with ERROR(PROTOCOL) before it is looked at, never executed, and ends the session.
//  - Every COMMAND (one position per actuator, n = bench.num_actuators()) is checked by the
//    SafetyGate, one SafetyMonitor per actuator (SI limits; bench units are converted with the
//    bench's BenchUnits), before any actuator moves. A refused command is answered with
//    ERROR(SAFETY, limit, value, limit value), the bench holds, and every further COMMAND of
//    that session is refused the same way (the refusal latches until the client reconnects).
//    With options.actuator_stiffness the forces are predicted coupled (safety_gate.h).
//  - Every measurement is checked too (finite, |force| ≤ force_hard); a violation is
//    answered with ERROR(SAFETY) and latches in the same way.
//  - On a silent client (no frame for heartbeat_timeout), a malformed frame, an unexpected
//    message or a disconnect of the commanding session (or of any session while none
//    commands), the bench is put in Hold() — it never moves to a new position and never
//    returns to zero — and the server goes on serving.
//  - Log lines carry client-supplied text (names) with control characters escaped.
//
// Lifecycle: the constructor binds and listens (so port() is known at once); Serve() calls
// the bench's Activate(), serves until Stop(), then holds and deactivates the bench. After a
// hold (explicit HOLD, disconnect, ...), the next accepted COMMAND resumes the bench with
// Activate() before Execute(): a TransferSystem must accept Activate() again after Hold().
#include <atomic>
#include <cstddef>
#include <cstdint>
#include <span>
#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "hybridtest/transfer/auth.h"
#include "hybridtest/transfer/bench_faults.h"
#include "hybridtest/transfer/frame.h"
#include "hybridtest/transfer/safety.h"
#include "hybridtest/transfer/safety_gate.h"
#include "hybridtest/transfer/server_loop.h"
#include "hybridtest/transfer/socket.h"
#include "hybridtest/transfer/transfer_system.h"

namespace hybridtest::transfer {

inline constexpr std::uint32_t kMaxHelloPayload = 4096;  // a HELLO's payload. Unit: [bytes].

struct BenchServerOptions {
  std::string host = "127.0.0.1";  // address to bind; non-loopback needs `token`
  std::uint16_t port = 7471;       // 0 picks a free port (see BenchServer::port())
  std::string token;               // shared secret the client's HELLO must carry; may be empty
                                   // on loopback
  double heartbeat_timeout = 10.0; // a client silent this long is dropped. Unit: [s].
  double handshake_timeout = 2.0;  // a connection has this long to complete HELLO. Unit: [s].
  std::size_t max_connections = 16;  // connections at once, sessions and openings together
                                     // (server_loop.h; OpenFresco too)
  double send_timeout = 2.0;       // longest wait to write one frame. Unit: [s].
  SafetyLimits limits;             // checked before every command. SI.
  // Actuator k's position before the first command, so that its increment is checked [m];
  // actuators beyond the list start at `start_position` if given (`limits` apply to every
  // actuator).
  std::vector<double> start_positions;
  std::optional<double> start_position;  // every actuator's start position. Unit: [m].
  std::optional<double> initial_stiffness;  // every actuator's stiffness for the force
                                            // prediction before two measurements. Unit: [N/m].
  // The specimen's stiffness in actuator coordinates (n × n), when known (a bench file's
  // specimen, an `initial_stiffness` matrix). Every command vector is then checked with the
  // coupled prediction f_last + K_a (a − x_last), so a move of one actuator loads the others
  // (safety_gate.h); its diagonal is each actuator's own stiffness until every actuator has a
  // measurement. Unit: [N/m].
  std::optional<Eigen::MatrixXd> actuator_stiffness;
  std::vector<Fault> faults;       // TEST FACILITY ONLY (bench_faults.h); empty in real use
  std::function<void(const std::string&)> log;  // one line per event; may be empty
};

// Each actuator's monitor in `gate` starts from its entry of options.start_positions, else
// from options.start_position if given (the servers' gates: bench and OpenFresco).
void SetStartPositions(SafetyGate& gate, const BenchServerOptions& options);

class BenchServer {
 public:
  // Binds and listens. Throws ConfigError for a non-loopback host without a token or
  // inconsistent limits, TransferError if the address cannot be bound (e.g. port in use).
  // `bench` must outlive the server.
  BenchServer(TransferSystem& bench, BenchServerOptions options);
  BenchServer(const BenchServer&) = delete;
  BenchServer& operator=(const BenchServer&) = delete;

  std::uint16_t port() const { return listener_.port(); }  // the bound port
  std::string address() const;                             // "HOST:PORT"

  // Activates the bench and serves clients until Stop(). Throws what the bench's Activate()
  // or Deactivate() throw; session errors are handled (hold, log, next client), never thrown.
  void Serve();

  // Asks Serve() to return within about 0.1 s. Safe from another thread or a signal handler.
  void Stop() noexcept { stop_.store(true); }

  long commands_received() const { return commands_received_.load(); }  // lifetime count
  long loop_turns() const { return loop_.turns(); }  // the loop's wake-ups (server_loop.h)

 private:
  struct Session {  // the state of one connection's session
    std::uint64_t last_sequence = 0;  // of the last request accepted; the next must be + 1
    bool refused = false;       // a safety refusal latched: every further COMMAND is refused
    std::string refused_limit;  // the limit of that refusal
    std::string refused_text;
    std::string end;            // why the session ended, if its handler ended it (the log)
  };
  using Connection = ServerLoop::Connection;
  // One complete frame of connection `c` (the codec's answer); false when it must end.
  bool HandleBytes(Connection& c, std::span<const std::uint8_t> bytes);
  void Closed(Connection& c, const ServerLoop::Closing& closing);
  bool Handshake(Connection& c, Session& session, const Frame& hello);
  // Handles one frame of an open session; returns false when the session must end.
  bool HandleFrame(Connection& c, Session& session, const Frame& frame);
  bool AnswerFailedMove(Connection& c, Session& session, const Frame& frame, long n);
  // A COMMAND: one position per actuator.
  bool HandleCommand(Connection& c, Session& session, const Frame& frame);
  // True if `c` may command (it claims the bench); else answers ERROR(BUSY).
  bool Commands(Connection& c, const Frame& frame);
  bool Send(Connection& c, const Frame& frame);
  void SendError(Connection& c, std::uint32_t sequence, int code, const std::string& limit,
                 double value, double limit_value, const std::string& text);
  void Log(const std::string& line) const;
  void HoldBench(const std::string& why);  // bench_.Hold(), remembered in bench_held_

  TransferSystem& bench_;
  BenchServerOptions options_;
  BenchUnits units_;
  SafetyGate gate_;  // check → move → check of every command received (n actuators)
  std::vector<GatedMove> moves_;       // (n) the last command's moves
  std::vector<Measurement> measured_;  // (n) what the last answer carries
  Listener listener_;
  std::atomic<bool> stop_{false};
  std::atomic<long> commands_received_{0};
  AuthThrottle auth_;
  std::map<int, Session> sessions_;  // by connection id
  ServerLoop loop_;  // connections, their limits and the commander
  bool bench_held_ = false;  // a COMMAND after a hold resumes the bench with Activate()
  std::vector<std::uint8_t> previous_measurement_;  // encoded, for the `duplicate` fault
};

}  // namespace hybridtest::transfer
