// The cost of the run state (runner/run_state.h) at every commit of a run with a physical
// slot, against the journal row alone.
//
// Method. A run of the paper's hybrid test (rotor, Heun, blade 1 on an in-process emulated
// cantilever bench with second-order lag, 2 ms delay and load-cell noise: the largest state
// an in-process bench has) is set up as the runner sets it up: substructures activated and
// tried once, scheme started. Each iteration then does, alternately and timed apart:
//   row     Journal::Append of one row with the physical policy (pwrite + fsync every row);
//   state   the same Append, then the run state captured (scheme and substructure states),
//           serialised and written atomically (temporary file, fsync, rename, directory sync)
//           — what the Session's file observer does at every commit.
// Counters: row_us and row_and_state_us (means, [µs]) and ratio = row_and_state / row, both
// measured in the same run on the same file system (the temporary directory).
#include <benchmark/benchmark.h>
#include <unistd.h>

#include <chrono>
#include <filesystem>

#include "hybridtest/io/config.h"
#include "hybridtest/io/run_spec_yaml.h"
#include "hybridtest/io/substructure_config.h"
#include "hybridtest/multibody/kane.h"
#include "hybridtest/runner/run_record.h"
#include "hybridtest/runner/run_state.h"
#include "hybridtest/schemes/scheme_config.h"

namespace hybridtest::bench {
namespace {

using Clock = std::chrono::steady_clock;

io::SimulationConfig EmulatedConfig() {
  const std::string text = R"(
model: {name: rotor, blades: 3}
integrator: {tableau: heun, dt: 0.001}
duration: 10.0
substructures:
  r1:
    type: physical
    transfer:
      type: emulated
      bench:
        units: {length: mm, force: N}
        seed: 1
        p0_mm: 0
        specimen: {type: linear, stiffness: 5250}
        actuator: {position_min_mm: -150, position_max_mm: 150, capacity_kN: 10,
                   velocity_limit_mm_per_s: 20, delay_ms: 2,
                   lag: {type: second_order, natural_frequency_hz: 10, damping_ratio: 0.8}}
        load_cell: {noise_std_N: 0.2, resolution_N: 0.01, offset_N: 0}
        settling: {tolerance_mm: 0.005, dwell_ms: 1}
        sampling: {window_ms: 1}
        timing: {overhead_ms: 0, internal_step_ms: 1}
        safety: {stroke_min_mm: -100, stroke_max_mm: 100, max_increment_mm: 2,
                 force_soft_kN: 0.25, force_hard_kN: 0.3, timeout_s: 5}
    setup: {p0: 0.0}
    safety: {stroke_min: -0.1, stroke_max: 0.1, max_increment: 0.002, force_soft: 250,
             force_hard: 300, timeout: 5}
)";
  return io::ParseSimulationConfig(YamlInput::FromText(text, "bench_run_state.yaml"));
}

void BM_RunStateOverhead(benchmark::State& state) {
  const io::SimulationConfig cfg = EmulatedConfig();
  runner::SubstructureList subs = io::MakeSubstructures(cfg, {});
  const multibody::Model& model = cfg.model.model;
  schemes::SlotInfo info{Eigen::VectorXd::Zero(3), Eigen::VectorXd::Constant(3, 0.002), {}};
  for (int s = 0; s < 3; ++s) {
    const auto k0 = subs[static_cast<std::size_t>(s)]->initial_stiffness();
    info.k0(s) = k0 ? (*k0)(0, 0) : 7200.0;
  }
  auto scheme = schemes::MakeScheme(cfg.scheme, cfg.tableau, cfg.dt, cfg.duration, cfg.steps,
                                    model, info);
  for (auto& s : subs) s->Activate();
  Eigen::VectorXd r0(3);
  for (int s = 0; s < 3; ++s) {
    const double d0 = 0.0;
    subs[static_cast<std::size_t>(s)]->Trial({&d0, 1}, {&r0(s), 1}, {0, 0, 0.0});
    subs[static_cast<std::size_t>(s)]->Commit();
  }
  scheme->Start(0.0, cfg.x0, r0);

  const auto dir = std::filesystem::temp_directory_path() /
                   ("hybridtest_bench_run_state_" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  const std::string csv = (dir / "run.csv").string();
  double row_s = 0.0, both_s = 0.0;
  long count = 0;
  {
    const io::RunSpec spec = io::CompileRunSpec(cfg);
    io::Journal journal(csv, runner::JournalChannels(spec),
                        runner::JournalMetadataFor(spec, subs, "bench"), io::SyncPolicy::kEveryRow);
    std::vector<double> row(journal.channels().size());
    for (std::size_t c = 0; c < row.size(); ++c) row[c] = 0.1234567890123 * static_cast<double>(c + 1);
    const std::string state_path = runner::RunStatePath(csv);
    for (auto _ : state) {
      row[0] += 1e-3;
      const auto t0 = Clock::now();
      journal.Append(row);
      const auto t1 = Clock::now();
      row[0] += 1e-3;
      journal.Append(row);
      runner::RunState run_state;
      run_state.rows = journal.rows();
      run_state.scheme = scheme->SaveState();
      for (const auto& s : subs) run_state.substructures.push_back({{"slot", "r"}, {"state", s->SaveState()}});
      runner::SaveRunState(state_path, run_state);
      const auto t2 = Clock::now();
      row_s += std::chrono::duration<double>(t1 - t0).count();
      both_s += std::chrono::duration<double>(t2 - t1).count();
      ++count;
    }
  }
  std::filesystem::remove_all(dir);
  state.counters["row_us"] = 1e6 * row_s / static_cast<double>(count);
  state.counters["row_and_state_us"] = 1e6 * both_s / static_cast<double>(count);
  state.counters["ratio"] = both_s / row_s;
}
BENCHMARK(BM_RunStateOverhead)->Name("RunState/EveryCommit")->Unit(benchmark::kMicrosecond);

}  // namespace
}  // namespace hybridtest::bench
