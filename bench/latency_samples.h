#pragma once
// Per-iteration wall time of a round-trip benchmark, reported as percentiles: each iteration
// of `state` times one call of `round_trip` (steady_clock) into a sample [µs]; the counters
// p50_us, p99_us (nearest rank below, index ⌊q·n⌋ of the sorted samples) and max_us follow.
#include <benchmark/benchmark.h>

#include <algorithm>
#include <chrono>
#include <cstddef>
#include <vector>

namespace hybridtest::bench_support {

// Runs the benchmark loop of `state`, timing `round_trip(i)` at iteration i = 0, 1, …; sets
// the percentile counters and returns the number of samples (iterations).
template <typename Fn>
std::size_t TimeRoundTrips(benchmark::State& state, Fn&& round_trip) {
  std::vector<double> samples_us;
  samples_us.reserve(1 << 16);
  long i = 0;
  for (auto _ : state) {
    const auto start = std::chrono::steady_clock::now();
    round_trip(i++);
    const auto stop = std::chrono::steady_clock::now();
    samples_us.push_back(std::chrono::duration<double, std::micro>(stop - start).count());
  }
  if (samples_us.empty()) return 0;
  std::sort(samples_us.begin(), samples_us.end());
  const auto at = [&](double q) {
    const auto rank = static_cast<std::size_t>(q * static_cast<double>(samples_us.size()));
    return samples_us[std::min(samples_us.size() - 1, rank)];
  };
  state.counters["p50_us"] = at(0.50);
  state.counters["p99_us"] = at(0.99);
  state.counters["max_us"] = samples_us.back();
  return samples_us.size();
}

}  // namespace hybridtest::bench_support
