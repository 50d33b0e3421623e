#pragma once
// Test doubles for the bench server tests: a linear-spring TransferSystem that records what it
// was asked to do (thread-safe: the server runs it in another thread), a BenchServer
// running in a background thread, and the options of a client for it.
#include <atomic>
#include <mutex>
#include <vector>

#include "hybridtest/transfer/bench_client.h"
#include "hybridtest/transfer/bench_server.h"
#include "hybridtest/transfer/transfer_system.h"
#include "transfer/serving_thread.h"

namespace hybridtest::transfer::testing {

// force = stiffness · (command − p0) in bench units (mm, N); position = command exactly.
class FakeBench final : public TransferSystem {
 public:
  static constexpr double kStiffness = 5.0;  // Unit: [N/mm].
  void Activate() override { ++activations; }
  int num_actuators() const override { return 1; }
  void Execute(std::span<const double> commands, std::span<Measurement> out) override {
    RequireOneActuator(commands, out, Describe());
    const double command = commands[0];
    std::lock_guard lock(mutex_);
    commands_.push_back(command);
    lab_time_ += 1.0;
    out[0] = Measurement{command, kStiffness * command + extra_force.load(), lab_time_};
  }
  void Hold() noexcept override { ++holds; }
  void Deactivate() override { ++deactivations; }
  BenchUnits bench_units() const override { return BenchUnits{1e-3, 1.0, "mm", "N"}; }
  std::string Describe() const override { return "fake linear bench (5 N/mm)"; }

  std::vector<double> commands() const {
    std::lock_guard lock(mutex_);
    return commands_;
  }

  std::atomic<int> activations{0};
  std::atomic<int> holds{0};
  std::atomic<int> deactivations{0};
  std::atomic<double> extra_force{0.0};  // added to every measured force. Unit: [N].

 private:
  mutable std::mutex mutex_;
  std::vector<double> commands_;
  double lab_time_ = 0.0;
};

// A BenchServer on 127.0.0.1, port 0, serving in a background thread until destroyed.
class ServerThread {
 public:
  ServerThread(TransferSystem& bench, BenchServerOptions options)
      : server_(bench, WithLoopbackPort0(std::move(options))) {}
  std::uint16_t port() const { return server_.port(); }
  BenchServer& server() { return server_; }
  bool failed() const { return serving_.failed(); }

 private:
  static BenchServerOptions WithLoopbackPort0(BenchServerOptions options) {
    options.host = "127.0.0.1";
    options.port = 0;
    return options;
  }
  BenchServer server_;
  ServingThread<BenchServer> serving_{server_};  // stops and joins before server_ goes
};

// Options for a BenchClient of `server`: waits at most `reply_timeout` [s] for a reply.
inline BenchClientOptions ClientFor(const ServerThread& server, double reply_timeout = 5.0) {
  BenchClientOptions o;
  o.port = server.port();
  o.reply_timeout = reply_timeout;
  return o;
}

}  // namespace hybridtest::transfer::testing
