// Round trip of one evaluation over Modbus/TCP on 127.0.0.1: ModbusTransfer::Execute (one
// function-16 write of command and sequence, then function-4 reads until the ack matches) to
// a controller with the default profile and an ideal actuator, so that the ack is there at
// the first read: two requests per evaluation.
//   ModbusRoundTrip/libmodbus: the controller of bench/modbus/modbus_bench_server.cc (C++,
//                              libmodbus's modbus_reply);
//   ModbusRoundTrip/pymodbus:  tests/transfer/modbus_server.py (Python asyncio, pymodbus).
// Reference, measured in the same run: BM_LoopbackRoundTrip (bench_transfer_latency.cc), the
// own bench protocol (one COMMAND → MEASUREMENT exchange). Run them together:
//   build/release/bench/hybridtest_bench --benchmark_filter='RoundTrip'
// Counters: p50_us, p99_us, max_us over the iterations [µs].
#include <benchmark/benchmark.h>

#include <cstddef>

#include "hybridtest/transfer/modbus/modbus_transfer.h"
#include "latency_samples.h"
#include "transfer/modbus_server_process.h"

namespace hybridtest::transfer::modbus {
namespace {

using hybridtest::testing::ModbusServerProcess;

void RoundTrips(benchmark::State& state, const ModbusServerProcess& server) {
  ModbusOptions options;
  options.port = server.port();
  ModbusTransfer transfer(options);
  transfer.Activate();
  const std::size_t evaluations = bench_support::TimeRoundTrips(state, [&](long i) {
    const double command = 0.5 * static_cast<double>(i % 8);  // [mm]
    benchmark::DoNotOptimize(ExecuteOne(transfer, command));
  });
  transfer.Deactivate();
  if (evaluations == 0) return;
  state.counters["requests_per_eval"] =
      static_cast<double>(transfer.requests()) / static_cast<double>(evaluations);
}

void BM_ModbusRoundTripLibmodbus(benchmark::State& state) {
  const ModbusServerProcess server({HYBRIDTEST_MODBUS_SERVER, "--listen", "127.0.0.1:0"});
  RoundTrips(state, server);
}
BENCHMARK(BM_ModbusRoundTripLibmodbus)->Name("ModbusRoundTrip/libmodbus")->Unit(benchmark::kMicrosecond);

void BM_ModbusRoundTripPymodbus(benchmark::State& state) {
  if (!hybridtest::testing::PymodbusAvailable()) {
    state.SkipWithError(hybridtest::testing::kPymodbusMissing);
    for (auto _ : state) {
    }
    return;
  }
  const ModbusServerProcess server = ModbusServerProcess::Pymodbus({});
  RoundTrips(state, server);
}
BENCHMARK(BM_ModbusRoundTripPymodbus)->Name("ModbusRoundTrip/pymodbus")->Unit(benchmark::kMicrosecond);

}  // namespace
}  // namespace hybridtest::transfer::modbus
