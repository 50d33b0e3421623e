#pragma once
// Client: a TransferSystem that drives a remote OpenFresco mode-A site server (wire.h) — a
// lab's OpenFresco SimApp server, or `hybridtest bench --protocol openfresco` — as a
// one-degree-of-freedom element (n = 1).
//
// Activate() connects (bounded by connect_timeout), sends the token preamble when a token is
// set (hybridtest servers only) and the plain-C header {1,1,1,0,0, 0,0,0,1,0, 256}.
// Execute(command) sends [3 | command | 0 | 0] (the element displacement, wire length unit),
// then asks getDisp (7) and getForce (10): the measurement is the element's measured
// displacement and resisting force, in wire units. Every reply is read within reply_timeout
// (poll); a timeout, a lost connection or a short reply is a TransferError naming host:port,
// after which the connection is closed. Measured values are not judged here (the caller's
// SafetyMonitor does that).
//
// The element displacement is what the server's setup maps to its actuator: a hybridtest
// server adds its own p0, so a run driving one uses a setup p0 of 0 (docs/openfresco.md).
// OpenFresco has no hold message: Hold() sends nothing (the site server keeps its actuator at
// the last command while no trial arrives) and never throws. Deactivate() sends 99 and closes.
// lab_time is the client's wall time since Activate() at the reply.
#include <chrono>
#include <cstdint>
#include <string>
#include <vector>

#include "hybridtest/transfer/openfresco/wire.h"
#include "hybridtest/transfer/socket.h"
#include "hybridtest/transfer/transfer_system.h"

namespace hybridtest::transfer::openfresco {

struct ClientOptions {
  std::string host = "127.0.0.1";
  std::uint16_t port = 8090;
  std::string token;             // hybridtest servers with a token only; empty otherwise
  BenchUnits units{1e-3, 1.0, "mm", "N"};  // units of the numbers on the wire
  double connect_timeout = 5.0;  // longest wait for the TCP connection. Unit: [s].
  double reply_timeout = 5.0;    // longest wait for any one reply. Unit: [s].
};

class Client final : public TransferSystem {
 public:
  // Does not connect (Activate() does). Throws ConfigError for non-positive timeouts.
  explicit Client(ClientOptions options);
  ~Client() override;

  void Activate() override;  // a no-op when already connected
  using TransferSystem::Execute;
  Measurement Execute(double command) override;
  void Hold() noexcept override {}
  void Deactivate() override;
  BenchUnits bench_units() const override { return options_.units; }
  std::string Describe() const override;

  bool is_connected() const { return socket_.is_open(); }
  const ClientOptions& options() const { return options_; }

 private:
  void Send(const std::vector<double>& values, const std::string& what);
  std::vector<double> Request(Action action, const std::string& what);
  [[noreturn]] void Fail(const std::string& message);

  ClientOptions options_;
  Header header_;
  Socket socket_;
  std::chrono::steady_clock::time_point activated_;
  long commands_ = 0;
};

}  // namespace hybridtest::transfer::openfresco
