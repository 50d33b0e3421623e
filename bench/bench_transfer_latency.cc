// Round-trip latency of one stage over the bench protocol: BenchClient::Execute (COMMAND →
// MEASUREMENT) over 127.0.0.1 to a BenchServer in another thread serving a trivial
// TransferSystem (force = k · command, no settling). This is the network and protocol cost a
// physical substructure adds to every stage, on top of the bench's own lab time.
//
// Counters: p50_us, p99_us, max_us: percentiles of the per-iteration wall time [µs].
// Reference: InProcessExecute calls the same trivial TransferSystem directly, so the ratio
// between the two is the cost of the wire.
#include <benchmark/benchmark.h>

#include <thread>

#include "hybridtest/transfer/bench_client.h"
#include "hybridtest/transfer/bench_server.h"
#include "latency_samples.h"

namespace hybridtest::transfer {
namespace {

class TrivialBench final : public TransferSystem {
 public:
  void Activate() override {}
  int num_actuators() const override { return 1; }
  void Execute(std::span<const double> commands, std::span<Measurement> out) override {
    lab_time_ += 1e-3;
    out[0] = Measurement{commands[0], 5.0 * commands[0], lab_time_};
  }
  void Hold() noexcept override {}
  void Deactivate() override {}
  BenchUnits bench_units() const override { return BenchUnits{1e-3, 1.0, "mm", "N"}; }
  std::string Describe() const override { return "trivial bench"; }

 private:
  double lab_time_ = 0.0;
};

// A small back-and-forth inside the stroke and the increment limit. Unit: [mm].
double CommandAt(long i) { return 0.5 * static_cast<double>(i % 8); }

void BM_LoopbackRoundTrip(benchmark::State& state) {
  TrivialBench bench;
  BenchServerOptions server_options;
  server_options.port = 0;
  server_options.limits.max_increment = 1.0;  // [m]: the ramp wraps around
  BenchServer server(bench, server_options);
  std::thread serving([&] { server.Serve(); });
  {
    BenchClientOptions client_options;
    client_options.port = server.port();
    BenchClient client(client_options);
    client.Activate();
    bench_support::TimeRoundTrips(
        state, [&](long i) { benchmark::DoNotOptimize(ExecuteOne(client, CommandAt(i))); });
    client.Deactivate();
  }
  server.Stop();
  serving.join();
}
BENCHMARK(BM_LoopbackRoundTrip)->Unit(benchmark::kMicrosecond);

void BM_InProcessExecute(benchmark::State& state) {
  TrivialBench bench;
  long i = 0;
  for (auto _ : state) benchmark::DoNotOptimize(ExecuteOne(bench, CommandAt(i++)));
}
BENCHMARK(BM_InProcessExecute)->Unit(benchmark::kMicrosecond);

}  // namespace
}  // namespace hybridtest::transfer
