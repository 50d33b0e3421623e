#pragma once
// BenchServer: serves one TransferSystem over TCP with the hybridtest bench protocol v1
// (docs/protocol.md), to one client at a time.
//
// Safety rules, in the order they are applied:
//  - It binds 127.0.0.1 by default and refuses to bind any non-loopback address unless a
//    shared token of at least 16 bytes (not only whitespace) is configured; with a token, a
//    HELLO carrying another token is refused (compared in constant time; five wrong tokens
//    from one address block — IPv4 /24, IPv6 /64 — lock that block out for a minute, logged,
//    and a global budget bounds wrong tokens from all addresses together; see auth.h).
//  - Connections are authenticated concurrently (HandshakeQueue): every accepted connection has
//    handshake_timeout to deliver its HELLO, read without blocking, so an idle or slow peer
//    never delays a real client. Once a session is open, every other connection is answered
//    ERROR(BUSY) and closed: a session in progress is never taken over.
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
//    message or a disconnect, the bench is put in Hold() — it never moves to a new position
//    and never returns to zero — and the server waits for the next client.
//  - Log lines carry client-supplied text (names) with control characters escaped.
//
// Lifecycle: the constructor binds and listens (so port() is known at once); Serve() calls
// the bench's Activate(), serves until Stop(), then holds and deactivates the bench. After a
// hold (explicit HOLD, disconnect, ...), the next accepted COMMAND resumes the bench with
// Activate() before Execute(): a TransferSystem must accept Activate() again after Hold().
#include <atomic>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "hybridtest/transfer/auth.h"
#include "hybridtest/transfer/bench_faults.h"
#include "hybridtest/transfer/handshake_queue.h"
#include "hybridtest/transfer/frame.h"
#include "hybridtest/transfer/safety.h"
#include "hybridtest/transfer/safety_gate.h"
#include "hybridtest/transfer/socket.h"
#include "hybridtest/transfer/transfer_system.h"

namespace hybridtest::transfer {

struct BenchServerOptions {
  std::string host = "127.0.0.1";  // address to bind; non-loopback needs `token`
  std::uint16_t port = 7471;       // 0 picks a free port (see BenchServer::port())
  std::string token;               // shared secret the client's HELLO must carry; may be empty
                                   // on loopback
  double heartbeat_timeout = 10.0; // a client silent this long is dropped. Unit: [s].
  double handshake_timeout = 2.0;  // a connection has this long to complete HELLO. Unit: [s].
  std::size_t max_pending = 16;    // connections awaiting HELLO at once; the oldest is dropped
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

 private:
  struct Session;
  // Reads pending connection i; runs its session if its HELLO completes one. Returns true if
  // a session ran (the queue was emptied).
  bool AdvanceHandshake(std::size_t i);
  void DropExpiredHandshakes();
  void ServeSession(Session& session);
  bool Handshake(Session& session, const Frame& hello);
  // Handles one frame of an open session; returns false when the session must end.
  bool HandleFrame(Session& session, const Frame& frame);
  bool AnswerFailedMove(Session& session, const Frame& frame, long n);
  // A COMMAND: one position per actuator.
  bool HandleCommand(Session& session, const Frame& frame);
  void RefuseBusyClient();
  bool Send(Session& session, const Frame& frame);
  void SendError(Session& session, std::uint32_t sequence, int code, const std::string& limit,
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
  HandshakeQueue handshakes_;
  AuthThrottle auth_;
  bool bench_held_ = false;  // a COMMAND after a hold resumes the bench with Activate()
  std::vector<std::uint8_t> previous_measurement_;  // encoded, for the `duplicate` fault
};

}  // namespace hybridtest::transfer
