// Round trip of one evaluation over ADS on 127.0.0.1: AdsTransfer::Execute (one sum write of
// fCommand and nCommandSeq, then sum reads until nAckSeq matches) to the TwinCAT PLC emulator
// (AdsServer, `hybridtest bench --protocol ads`) in another thread, serving an ideal emulated
// bench (no lag, no settling), so that the ack is there at the first read: two requests per
// evaluation.
// Reference, measured in the same run: BM_LoopbackRoundTrip (bench_transfer_latency.cc, the
// own bench protocol) and ModbusRoundTrip/* (bench_modbus_latency.cc). Run them together:
//   build/release/bench/hybridtest_bench --benchmark_filter='RoundTrip'
// Counters: p50_us, p99_us, max_us over the iterations [µs]; requests_per_eval.
#include <benchmark/benchmark.h>
#include <yaml-cpp/yaml.h>

#include <thread>

#include "hybridtest/transfer/ads/ads_server.h"
#include "hybridtest/transfer/ads/ads_transfer.h"
#include "hybridtest/transfer/emulated_bench.h"
#include "latency_samples.h"

namespace hybridtest::transfer::ads {
namespace {

// An ideal bench (examples/rotor/bench-ideal.yaml): a 7200 N/m spring, no lag, no noise.
constexpr const char* kIdealBench = R"(bench:
  units: {length: mm, force: N}
  pacing: accelerated
  p0_mm: 20
  specimen: {type: linear, stiffness: 7200}
  actuator: {position_min_mm: -150, position_max_mm: 150, capacity_kN: 10,
             velocity_limit_mm_per_s: 1000, lag: {type: none}, delay_ms: 0}
  load_cell: {noise_std_N: 0, resolution_N: 0, offset_N: 0}
  settling: {tolerance_mm: 0.001, dwell_ms: 0}
  sampling: {window_ms: 1}
  timing: {overhead_ms: 0, internal_step_ms: 1}
)";

void BM_AdsRoundTrip(benchmark::State& state) {
  const EmulatedBenchSpec spec = ParseEmulatedBenchSpec(YAML::Load(kIdealBench)["bench"], "bench");
  std::unique_ptr<TransferSystem> bench = MakeEmulatedBench(spec);
  AdsServerOptions server_options;
  server_options.port = 0;
  UseBenchSafety(server_options, spec);
  AdsServer server(*bench, server_options);
  std::thread serving([&] { server.Serve(); });
  AdsOptions options;
  options.endpoint.tcp_port = server.port();
  AdsTransfer transfer(options);
  transfer.Activate();
  std::vector<Measurement> out(1);
  const std::size_t evaluations = bench_support::TimeRoundTrips(state, [&](long i) {
    const double command = 20.0 + 0.5 * static_cast<double>(i % 8);  // [mm]
    transfer.Execute(std::span<const double>(&command, 1), out);
    benchmark::DoNotOptimize(out[0].force);
  });
  transfer.Deactivate();
  server.Stop();
  serving.join();
  if (evaluations == 0) return;
  state.counters["requests_per_eval"] =
      static_cast<double>(transfer.requests()) / static_cast<double>(evaluations);
}
BENCHMARK(BM_AdsRoundTrip)->Name("AdsRoundTrip/emulator")->Unit(benchmark::kMicrosecond);

}  // namespace
}  // namespace hybridtest::transfer::ads
