#pragma once
// Client: a TransferSystem that drives a remote OpenFresco mode-A site server (wire.h) — a
// lab's OpenFresco SimApp server, or `hybridtest bench --protocol openfresco` — as an element
// of n degrees of freedom (ClientOptions::dofs, default 1). Each degree of freedom is one
// channel of ours: num_actuators() = n, and a run reaches n > 1 through a substructure of n
// slots (setup T = identity, p0 = 0: the site applies its own setup).
//
// Activate() connects (bounded by connect_timeout), sends the token preamble when a token is
// set (hybridtest servers only) and the plain-C header {n,n,n,0,0, 0,0,0,n,0, dataSize} with
// dataSize = max(256, 3n+2, n²).
// Execute(commands) sends one trial [3 | d (n) | v = 0 (n) | a = 0 (n)] (the element
// displacements, wire length unit), then asks getDisp (7) and getForce (10): out[k] is the
// element's measured displacement and resisting force of degree of freedom k, in wire units
// (words 0..n−1 of each reply). Every reply must be exactly dataSize float64 values, read
// within reply_timeout (poll); a timeout, a lost connection or a reply of another length (fewer
// bytes, or bytes beyond it) is a TransferError naming host:port and the lengths, after which
// the connection is closed. Measured values are not judged here (the caller's safety monitors
// do that). The scalar Execute(command) serves n = 1 only.
//
// The element displacement is what the server's setup maps to its actuators: a hybridtest
// server adds its own p0, so a run driving one uses a setup p0 of 0 (docs/openfresco.md).
// OpenFresco has no hold message: Hold() sends nothing (the site server keeps its actuators at
// the last command while no trial arrives) and never throws. Deactivate() sends 99 and closes.
// lab_time is the client's wall time since Activate() at the reply.
#include <chrono>
#include <cstdint>
#include <span>
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
  int dofs = 1;                  // n, the element's degrees of freedom (1 to kMaxDofs)
  BenchUnits units{1e-3, 1.0, "mm", "N"};  // units of the numbers on the wire
  double connect_timeout = 5.0;  // longest wait for the TCP connection. Unit: [s].
  double reply_timeout = 5.0;    // longest wait for any one reply. Unit: [s].
  std::string token_file;        // the file `token` was read from ("": none); a run records it
};

class Client final : public TransferSystem {
 public:
  // Does not connect (Activate() does). Throws ConfigError for non-positive timeouts or a
  // `dofs` outside 1..kMaxDofs.
  explicit Client(ClientOptions options);
  ~Client() override;

  void Activate() override;  // a no-op when already connected
  void Execute(std::span<const double> commands, std::span<Measurement> out) override;
  int num_actuators() const override { return options_.dofs; }
  void Hold() noexcept override {}
  void Deactivate() override;
  BenchUnits bench_units() const override { return options_.units; }
  std::string Describe() const override;

  bool is_connected() const { return socket_.is_open(); }
  const ClientOptions& options() const { return options_; }

 private:
  void Send(const std::vector<double>& values, const std::string& what);
  std::vector<double> Request(Action action, const std::string& what);
  // Reads one reply of exactly dataSize words; checks that nothing follows it.
  std::vector<double> ReadReply(const std::string& what);
  // Fails if the server has sent bytes nobody asked for (a reply longer than dataSize).
  void CheckNothingPending(const std::string& after);
  [[noreturn]] void Fail(const std::string& message);

  ClientOptions options_;
  Header header_;
  Socket socket_;
  std::chrono::steady_clock::time_point activated_;
  long commands_ = 0;
  std::vector<double> trial_;  // [3 | d | v | a], reused
};

}  // namespace hybridtest::transfer::openfresco
