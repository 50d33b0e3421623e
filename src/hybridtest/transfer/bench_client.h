#pragma once
// BenchClient: a TransferSystem that drives a remote bench over TCP with the hybridtest bench
// protocol v1 (docs/protocol.md), e.g. one served by `hybridtest bench`.
//
// Guarantees:
//  - TCP_NODELAY; connect bounded by connect_timeout; every read bounded by reply_timeout
//    (poll), so no call blocks without a bound.
//  - Execute() sends COMMAND with the next sequence number and accepts only the MEASUREMENT
//    that echoes it. A stale or duplicate sequence number, a corrupted frame (CRC, magic,
//    length, type), a timeout or a lost connection is a TransferError; the message names
//    host:port and the command that was waited for. After a TransferError the connection is
//    closed (its state is unknown); the server holds the bench when it sees the disconnect.
//  - An ERROR(SAFETY) answer becomes a SafetyStop carrying the server's limit, value and limit
//    value (SI); the connection stays open so that Hold() and Deactivate() still work.
//  - Hold() sends HOLD and waits at most hold_timeout for HOLD_ACK; it never throws.
//  - The client does not judge measurement values (NaN, force spikes): that is the job of the
//    caller's SafetyMonitor, which then has the full exchange history.
//
// Sequence numbers: HELLO is 1, every further request takes the next number.
// The client sends no heartbeats on its own; a caller that may stay idle longer than the
// server's heartbeat_timeout (welcome().heartbeat_timeout) calls Heartbeat().
#include <cstdint>
#include <optional>
#include <string>

#include "hybridtest/transfer/protocol.h"
#include "hybridtest/transfer/safety.h"
#include "hybridtest/transfer/socket.h"
#include "hybridtest/transfer/transfer_system.h"

namespace hybridtest::transfer {

struct BenchClientOptions {
  std::string host = "127.0.0.1";
  std::uint16_t port = 7471;
  std::string token;                    // must match the server's; empty if it has none
  std::string client_name = "hybridtest";
  double connect_timeout = 5.0;  // longest wait for the TCP connection. Unit: [s].
  double reply_timeout = 5.0;    // longest wait for any one reply. Unit: [s].
  double hold_timeout = 0.5;     // longest wait for HOLD_ACK in Hold(). Unit: [s].
  // The caller's own safety limits (SI), if any: Activate() refuses a bench whose announced
  // limits do not contain them (limits_check.h), naming `limits_where` (a config key path).
  std::optional<SafetyLimits> expected_limits;
  std::string limits_where = "safety";
};

class BenchClient final : public TransferSystem {
 public:
  // Does not connect (Activate() does). Throws ConfigError for non-positive timeouts.
  explicit BenchClient(BenchClientOptions options);
  ~BenchClient() override;

  // Connects, sends HELLO and reads WELCOME. Throws TransferError (e.g. wrong token, version),
  // or ConfigError (after closing the connection) if expected_limits exceed the bench's.
  // Again after Hold() with the session still open: a HEARTBEAT only (reconnects if the
  // server dropped the session meanwhile).
  void Activate() override;
  // A bench of several actuators (its WELCOME says how many; 1 before Activate()): one COMMAND
  // with every position, one MEASUREMENT with every actuator's sample.
  int num_actuators() const override { return welcome_ ? welcome_->actuators : 1; }
  void Execute(std::span<const double> commands, std::span<Measurement> out) override;
  // Real time: every Execute sends one command and returns the server's measurement at once;
  // the server's plant runs on the server's own clock (`hybridtest bench --real-time CONFIG`).
  // A server that settles every move (an emulated bench) makes every tick late.
  void StartPaced(double /*tick*/, const Clock& /*clock*/) override {}
  bool can_run_paced() const override { return true; }
  void Hold() noexcept override;
  // HOLD → HOLD_ACK, BYE → BYE, close. A no-op when not connected.
  void Deactivate() override;
  // The server's units; valid after Activate() (defaults before).
  BenchUnits bench_units() const override;
  std::string Describe() const override;
  // The limits of the WELCOME, after Activate(); empty before.
  BenchAnnouncement Announce() const override;
  // READ → MEASUREMENT: every actuator's position and force without moving (after
  // Activate()); nullopt when not connected, or when the server cannot read or does not know
  // READ (an older server answers ERROR and may end the session). Never throws.
  std::optional<std::vector<Measurement>> ReadAll() override;

  // HEARTBEAT → HEARTBEAT_ACK round trip. Throws TransferError.
  void Heartbeat();

  bool is_connected() const { return socket_.is_open(); }
  // What the server announced; empty before Activate().
  const std::optional<WelcomeMessage>& welcome() const { return welcome_; }
  const BenchClientOptions& options() const { return options_; }

 private:
  std::string Endpoint() const;
  // Sends `frame`, then reads the reply with the same sequence number and type `expected`.
  // `waiting_for` completes "while waiting for ..." in error messages.
  Frame Exchange(const Frame& frame, MessageType expected, const std::string& waiting_for,
                 double timeout);
  [[noreturn]] void Fail(const std::string& message);

  BenchClientOptions options_;
  Socket socket_;
  std::uint32_t next_sequence_ = 1;
  std::optional<WelcomeMessage> welcome_;
};

}  // namespace hybridtest::transfer
