#pragma once
// Server: serves one TransferSystem to OpenFresco mode-A clients (wire.h) — OpenSees's
// `expElement genericClient`, OpenFresco's ECGenericTCP control or plain-C client — through a
// ExpSetup (setup.h), one client at a time. `hybridtest bench --protocol openfresco` runs it.
//
// Session: header (optionally preceded by the token preamble), then messages until the
// client sends 99 (DIE, ends the session cleanly), 98 (shutdown: ends the session) or leaves.
//   3  setTrialResponse → the bench moves to p0 + T d now (no reply)
//   5  commitState      → nothing to do (no reply)
//   6  getDaqResponse   → blocks disp|vel|accel|force|time of sizes sizeDaq; the first word of
//                         each block holds the actuator's measured offset x = p − p0, 0, 0,
//                         measured force f, lab time [s]; the rest is zero
//   7  getDisp          → Tᵀ(T Tᵀ)⁻¹ x             8, 9  getVel, getAccel → the trial v, a
//                                                        projected on T (zeros if not sent)
//   10 getForce         → q = Tᵀ f                 11 getTime → lab time of the measurement [s]
//   12, 13 getInitialStiff, getTangentStiff → Tᵀ K_a T (column-major)  14, 15 → zeros (n × n)
// with the n_act actuators of the setup (T n_act × n; setup.h; n_act = 1: one row t, K_a = K0):
// the bench moves every actuator to p0 + T d, and the first n_act words of the disp and force
// DAQ blocks hold the actuators' values.
// Before the first trial of a session, getDisp/getForce/getDaqResponse report zeros.
//
// Safety — the rules of BenchServer (bench_server.h), with the same SafetyMonitor:
//  - binds 127.0.0.1 by default; a non-loopback address needs a shared token of at least 16
//    bytes (auth.h), which clients present in the token preamble; a preamble with another
//    token (or one the server does not expect) is refused (compared in constant time; five
//    wrong or missing tokens from one address block — IPv4 /24, IPv6 /64 — lock that block out
//    for a minute, and a global budget bounds wrong tokens from all addresses together; see
//    auth.h). OpenSees sends no preamble: reach a remote bench through a tunnel.
//  - connections are served by the shared ServerLoop (server_loop.h) with its limits: every
//    accepted connection has handshake_timeout [s] to deliver its preamble and header, read
//    without blocking, so an idle, slow or dripping peer never delays another client; a begun
//    message must be complete within heartbeat_timeout; at most max_connections at once (one
//    more closes the one that waited longest for its header); the process's file limit never
//    makes it spin. The session whose opening is accepted commands (the protocol has no
//    reads without a session): every other waiting connection is then closed, and a
//    connection during a session is logged and closed at once — one session at a time.
//  - a trial is executed only while its client is still connected: a trial read after the
//    client has closed or reset its end (it gave up waiting, or vanished) is logged, never
//    executed, and puts the bench in Hold().
//  - every trial command is checked (SafetyLimits, SI) before the bench moves, and every
//    measurement after; a refusal holds the bench and ends the session. With several
//    actuators every command of a trial is checked before any actuator moves, the forces
//    predicted coupled, f_last + K_a (a − x_last), with options.actuator_stiffness or else the
//    setup's K_a (safety_gate.h); one actuator predicts from its own secant, starting from
//    options.initial_stiffness or K0. The OpenFresco
//    protocol has no error message, so the client learns of it by the closed connection.
//  - a malformed opening, an unknown action, a non-finite trial value, a message not complete
//    within heartbeat_timeout, a client silent for heartbeat_timeout, or a disconnect is
//    logged and puts the bench in Hold() (it never moves to a new position by itself); the
//    session ends and the server waits for the next client.
// After a hold, the next trial resumes the bench with Activate() before Execute().
#include <atomic>
#include <cstdint>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "hybridtest/transfer/auth.h"
#include "hybridtest/transfer/bench_server.h"
#include "hybridtest/transfer/openfresco/setup.h"
#include "hybridtest/transfer/openfresco/wire.h"
#include "hybridtest/transfer/safety.h"
#include "hybridtest/transfer/safety_gate.h"
#include "hybridtest/transfer/server_loop.h"
#include "hybridtest/transfer/socket.h"
#include "hybridtest/transfer/transfer_system.h"

namespace hybridtest::transfer::openfresco {

class Server {
 public:
  // Binds and listens. Uses host, port, token, heartbeat_timeout, handshake_timeout,
  // max_connections, send_timeout, limits, start_position(s), initial_stiffness (default: the
  // setup's K0), actuator_stiffness (default: the setup's K_a) and log of `options`.
  // Throws ConfigError for a non-loopback host without a token, an invalid setup, inconsistent
  // limits or test faults (they belong to the hybridtest protocol); TransferError if the
  // address cannot be bound. `bench` must outlive the server.
  Server(TransferSystem& bench, ExpSetup setup, BenchServerOptions options);
  Server(const Server&) = delete;
  Server& operator=(const Server&) = delete;
  ~Server();

  std::uint16_t port() const { return listener_.port(); }
  std::string address() const;  // "HOST:PORT"
  const ExpSetup& setup() const { return setup_; }

  // Activates the bench and serves clients until Stop(); then holds and deactivates it.
  // Session errors are logged and end the session; they are never thrown.
  void Serve();
  // Asks Serve() to return within about 0.1 s. Safe from another thread or a signal handler.
  void Stop() noexcept { stop_.store(true); }

  long sessions_served() const { return sessions_.load(); }      // lifetime count
  long trials_executed() const { return trials_.load(); }        // lifetime count
  long auth_failures() const { return auth_failures_.load(); }   // wrong tokens compared
  long loop_turns() const { return loop_.turns(); }  // the loop's wake-ups (server_loop.h)

 private:
  struct Session;
  using Connection = ServerLoop::Connection;
  // The codec: the opening's size (wire.h), then dataSize × 8 bytes per message.
  std::size_t Measure(const Connection& c, std::span<const std::uint8_t> bytes) const;
  // One complete opening or message of `c`; false when its connection must end.
  bool HandleBytes(Connection& c, std::span<const std::uint8_t> bytes);
  void Closed(Connection& c, const ServerLoop::Closing& closing);
  // Token and header; the session, or null (logged) when the opening is refused.
  std::unique_ptr<Session> OpenSession(const Connection& c, std::span<const std::uint8_t> bytes);
  bool HandleMessage(Connection& c, Session& session, const std::vector<double>& message);
  bool HandleTrial(Connection& c, Session& session, const std::vector<double>& message);
  bool Reply(Connection& c, Session& session, const std::vector<double>& values);
  std::vector<double> DaqResponse(const Session& session) const;
  void HoldBench(const std::string& why);
  void Log(const std::string& line) const;

  TransferSystem& bench_;
  ExpSetup setup_;
  BenchServerOptions options_;
  BenchUnits bench_units_;
  // Check → move → check of every trial: one monitor per actuator of the setup, every command
  // of a trial checked before any actuator moves.
  SafetyGate gate_;
  std::vector<GatedMove> moves_;  // (n_act) the last trial's moves
  Listener listener_;
  std::atomic<bool> stop_{false};
  std::atomic<long> sessions_{0};
  std::atomic<long> trials_{0};
  std::atomic<long> auth_failures_{0};
  AuthThrottle auth_;
  std::unique_ptr<Session> session_;  // the open session (its connection commands), or null
  int session_id_ = 0;                // its connection's id
  ServerLoop loop_;  // connections, their limits and the commander
  bool bench_held_ = false;
};

}  // namespace hybridtest::transfer::openfresco
