// The runner's own cost per Runge–Kutta stage, without a bench: everything the Session
// does besides the right-hand side (slot displacements, substructure trials and commits, the
// stepper's linear combinations, the journal row, statistics and progress).
//
// Method. A whole run of the paper's numerical rotor (3 numerical blades, Heun, h = 1 ms,
// kSteps steps; journal to a temporary file, progress quiet) goes through the real
// Session. In the same benchmark iteration the RHS cost is measured right after the
// run: kSteps·2 CalcStateDerivative<double> calls on rotor states (its cost does not depend on
// the state: no state-dependent branches), giving rhs_ns per call.
//
//   Runner/WholeRun             uninstrumented: per_stage_ns = wall time of the run / stages,
//                               overhead_ns = per_stage_ns − rhs_ns (the mean overhead).
//   Runner/StageSeam            the same run with every substructure wrapped (the stage
//                               seam): slot 1's Trial records steady_clock::now(), so the
//                               interval between two consecutive trials of slot 1 is one whole
//                               stage. Per-stage overhead = interval − rhs_ns; counters
//                               overhead_p50_ns, overhead_p99_ns over all stages, and p50/p99
//                               for stage 0 (which also commits and writes the journal row) and
//                               stage 1 apart (Heun: the distribution is bimodal, so the p50
//                               over all stages sits between the two). The wrapper adds one
//                               virtual call and one clock read (≈ 20 ns) per stage. The mean
//                               of WholeRun is higher than these: it also holds the journal's
//                               fsync every 1000 rows and at the end, and opening/finishing
//                               the journal and sidecar.
//   Runner/SessionStep/*        one committed step of the paper's dummy test (slot r1 on the
//                               numerical loopback; Heun) held in memory: `bare` is a loop
//                               written by hand around the same scheme and substructures (no
//                               observers, no records: the reference), `session` is
//                               Session::Step() with one observer that reads every trial and
//                               row; counter ratio_to_bare in the session's row.
//   Runner/JournalAppend/batched    Journal::Append of one rotor row (12 channels), the policy
//   Runner/JournalAppend/every_row  of numerical runs (fsync every 1000 rows) and of runs with
//                               a physical substructure (fflush + fsync every row).
#include <benchmark/benchmark.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <filesystem>
#include <memory>
#include <random>
#include <vector>

#include "hybridtest/io/config.h"
#include "hybridtest/io/run_spec_yaml.h"
#include "hybridtest/io/substructure_config.h"
#include "hybridtest/multibody/kane.h"
#include "hybridtest/runner/open_run.h"
#include "hybridtest/runner/run_record.h"
#include "hybridtest/runner/session.h"
#include "hybridtest/schemes/scheme_config.h"

namespace hybridtest::bench {
namespace {

using Clock = std::chrono::steady_clock;
constexpr long kSteps = 2000;  // 2 s of simulated time

// examples/rotor/numerical.yaml, shortened to kSteps steps.
io::SimulationConfig RotorConfig() {
  const std::string text =
      "model: {name: rotor, blades: 3}\n"
      "integrator: {tableau: heun, dt: 0.001}\n"
      "duration: " + std::to_string(static_cast<double>(kSteps) * 1e-3) + "\n";
  return io::ParseSimulationConfig(YamlInput::FromText(text, "bench_runner.yaml"));
}

std::string TempJournalPath(const char* name) {
  return (std::filesystem::temp_directory_path() /
          ("hybridtest_bench_" + std::to_string(::getpid()) + "_" + name + ".csv"))
      .string();
}

void RemoveJournal(const std::string& path) {
  std::error_code ec;
  std::filesystem::remove(path, ec);
  std::filesystem::remove(io::SidecarPath(path), ec);
}

// Mean cost of one RHS evaluation [ns] over `calls` calls on running-rotor states.
double MeasureRhsNs(const multibody::Model& model, long calls) {
  std::mt19937_64 rng(1);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  std::vector<Eigen::VectorXd> xs, rs;
  for (int k = 0; k < 64; ++k) {
    Eigen::VectorXd x(8);
    x << 0.01 * unit(rng), 0.01 * unit(rng), 0.01 * unit(rng), 10.0 * unit(rng),
        0.5 * unit(rng), 0.5 * unit(rng), 0.5 * unit(rng), 20.0 * unit(rng);
    xs.push_back(x);
    rs.push_back(7.2e3 * x.head(3));
  }
  multibody::Data<double> data(model);
  Eigen::VectorXd xdot(8);
  const auto start = Clock::now();
  for (long k = 0; k < calls; ++k) {
    multibody::CalcStateDerivative<double>(model, data, 1e-3 * static_cast<double>(k % 2000),
                                           xs[k & 63], rs[k & 63], xdot);
    benchmark::DoNotOptimize(xdot.data());
    benchmark::ClobberMemory();
  }
  return std::chrono::duration<double, std::nano>(Clock::now() - start).count() /
         static_cast<double>(calls);
}

io::RunSpec QuietSpec(const io::SimulationConfig& cfg, const std::string& path) {
  io::RunSpec spec = io::CompileRunSpec(cfg);
  spec.output.csv_path = path;
  spec.output.command = "bench";
  spec.quiet = true;
  return spec;
}

void BM_WholeRun(benchmark::State& state) {
  const io::SimulationConfig cfg = RotorConfig();
  const std::string path = TempJournalPath("whole_run");
  const long stages = 2 * kSteps + 1;  // + the last trial at x_N
  double run_s = 0.0, rhs_ns = 0.0;
  long runs = 0;
  for (auto _ : state) {
    io::RunSpec spec = QuietSpec(cfg, path);
    runner::OpenedRun opened = runner::OpenRun(spec, {.overwrite = true});  // the front door
    runner::Session session(std::move(spec), std::move(opened));
    const auto start = Clock::now();
    session.Run();
    run_s += std::chrono::duration<double>(Clock::now() - start).count();
    rhs_ns += MeasureRhsNs(cfg.model.model, 2 * kSteps);
    ++runs;
  }
  RemoveJournal(path);
  const double per_stage_ns = 1e9 * run_s / static_cast<double>(runs * stages);
  state.counters["per_stage_ns"] = per_stage_ns;
  state.counters["rhs_ns"] = rhs_ns / static_cast<double>(runs);
  state.counters["overhead_ns"] = per_stage_ns - rhs_ns / static_cast<double>(runs);
}
BENCHMARK(BM_WholeRun)->Name("Runner/WholeRun")->Unit(benchmark::kMillisecond);

// Forwards to a substructure; slot 1's trials are time-stamped.
class StampingSubstructure final : public substructures::Substructure {
 public:
  StampingSubstructure(std::unique_ptr<substructures::Substructure> inner,
                       std::vector<Clock::time_point>* stamps)
      : inner_(std::move(inner)), stamps_(stamps) {}
  void Trial(std::span<const double> d, std::span<double> r,
             const substructures::TrialContext& context) override {
    if (stamps_ != nullptr) stamps_->push_back(Clock::now());
    inner_->Trial(d, r, context);
  }
  void Commit() override { inner_->Commit(); }
  std::string Describe() const override { return inner_->Describe(); }

 private:
  std::unique_ptr<substructures::Substructure> inner_;
  std::vector<Clock::time_point>* stamps_;
};

double Percentile(std::vector<double>& v, double q) {
  std::sort(v.begin(), v.end());
  return v[std::min(v.size() - 1, static_cast<std::size_t>(q * static_cast<double>(v.size())))];
}

void BM_StageSeam(benchmark::State& state) {
  const io::SimulationConfig cfg = RotorConfig();
  const std::string path = TempJournalPath("stage_seam");
  std::vector<Clock::time_point> stamps;
  stamps.reserve(2 * kSteps + 1);
  std::vector<double> all, stage0, stage1;  // intervals [ns]
  double rhs_ns = 0.0;
  long runs = 0;
  for (auto _ : state) {
    io::RunSpec spec = QuietSpec(cfg, path);
    for (std::size_t s = 0; s < spec.substructures.size(); ++s) {
      const substructures::SubstructureSpec inner = spec.substructures[s];
      spec.substructures[s].custom = [inner, s, &stamps] {
        return std::make_unique<StampingSubstructure>(inner.Build(), s == 0 ? &stamps : nullptr);
      };
    }
    runner::OpenedRun opened = runner::OpenRun(spec, {.overwrite = true});
    runner::Session session(std::move(spec), std::move(opened));
    stamps.clear();
    session.Run();
    // Trial k of slot 1 is stage k % 2 of step k / 2 (Heun: two stages).
    for (std::size_t k = 0; k + 1 < stamps.size(); ++k) {
      const double ns = std::chrono::duration<double, std::nano>(stamps[k + 1] - stamps[k]).count();
      all.push_back(ns);
      (k % 2 == 0 ? stage0 : stage1).push_back(ns);
    }
    rhs_ns += MeasureRhsNs(cfg.model.model, 2 * kSteps);
    ++runs;
  }
  RemoveJournal(path);
  const double rhs = rhs_ns / static_cast<double>(runs);
  state.counters["rhs_ns"] = rhs;
  state.counters["overhead_p50_ns"] = Percentile(all, 0.50) - rhs;
  state.counters["overhead_p99_ns"] = Percentile(all, 0.99) - rhs;
  state.counters["stage0_overhead_p50_ns"] = Percentile(stage0, 0.50) - rhs;
  state.counters["stage0_overhead_p99_ns"] = Percentile(stage0, 0.99) - rhs;
  state.counters["stage1_overhead_p50_ns"] = Percentile(stage1, 0.50) - rhs;
  state.counters["stage1_overhead_p99_ns"] = Percentile(stage1, 0.99) - rhs;
}
BENCHMARK(BM_StageSeam)->Name("Runner/StageSeam")->Unit(benchmark::kMillisecond);

void BM_JournalAppend(benchmark::State& state, io::SyncPolicy policy, const char* name) {
  const io::SimulationConfig cfg = RotorConfig();
  const io::RunSpec spec = io::CompileRunSpec(cfg);
  const runner::SubstructureList subs = io::MakeSubstructures(cfg, {});
  const std::string path = TempJournalPath(name);
  {
    io::Journal journal(path, runner::JournalChannels(spec),
                        runner::JournalMetadataFor(spec, subs, "bench"), policy);
    // A typical row: t, x (8), r (3), with full-length digits.
    std::vector<double> row(journal.channels().size());
    for (std::size_t c = 0; c < row.size(); ++c) row[c] = 0.1234567890123 * static_cast<double>(c + 1);
    for (auto _ : state) {
      row[0] += 1e-3;
      journal.Append(row);
    }
  }
  RemoveJournal(path);
}
// The paper's dummy test in memory, long enough for any number of benchmark iterations.
io::RunSpec DummySpec() {
  io::RunSpec spec = io::CompileRunSpec(io::ParseSimulationConfig(YamlInput::FromText(
      "model: {name: rotor, blades: 3}\n"
      "integrator: {tableau: heun, dt: 0.001}\n"
      "duration: 100000\n"
      "substructures:\n"
      "  r1:\n"
      "    type: physical\n"
      "    transfer: {type: loopback, law: {type: linear, stiffness: 5250}}\n"
      "    safety: defaults\n",
      "bench_session.yaml")));
  spec.output.files = false;
  spec.quiet = true;
  return spec;
}

// The reference: the same scheme and substructures stepped by hand, nothing recorded.
void BM_BareLoop(benchmark::State& state) {
  const io::RunSpec spec = DummySpec();
  const multibody::Model& model = spec.model.model;
  runner::SubstructureList subs;
  for (const auto& s : spec.substructures) subs.push_back(s.Build());
  schemes::SlotInfo info{Eigen::VectorXd::Constant(3, 5250.0), Eigen::VectorXd::Constant(3, 0.005), {}};
  auto scheme = schemes::MakeScheme(spec.scheme.config, spec.scheme.tableau, spec.scheme.dt,
                                    spec.scheme.duration, spec.scheme.steps, model, info);
  for (auto& s : subs) s->Activate();
  schemes::SeamOf seam([&](const schemes::TrialPoint& at, const Eigen::VectorXd& d,
                           Eigen::Ref<Eigen::VectorXd> r) {
    for (std::size_t s = 0; s < subs.size(); ++s) {
      const auto i = static_cast<Eigen::Index>(s);
      subs[s]->Trial({&d(i), 1}, {&r(i), 1}, {at.step, at.stage, at.t});
    }
  });
  schemes::RowSinkOf rows([](double, const Eigen::VectorXd&, const Eigen::VectorXd&) {});
  Eigen::VectorXd r0 = Eigen::VectorXd::Zero(3), d0 = Eigen::VectorXd::Zero(3);
  seam.Trial({0, 0, 0.0}, d0, r0);
  scheme->Start(0.0, spec.x0, r0);
  for (auto _ : state) {
    scheme->Step(seam, rows);
    for (auto& s : subs) s->Commit();
    benchmark::DoNotOptimize(scheme->committed().x.data());
  }
  state.counters["ns_per_step"] = benchmark::Counter(
      static_cast<double>(state.iterations()), benchmark::Counter::kIsRate | benchmark::Counter::kInvert);
}
BENCHMARK(BM_BareLoop)->Name("Runner/SessionStep/bare");

void BM_SessionStep(benchmark::State& state) {
  class Reader final : public runner::SessionObserver {
   public:
    void OnTrial(const runner::TrialEvent& e) override { sum += e.r[0]; }
    void OnCommit(const runner::CommitEvent& e) override { sum += e.row[1]; }
    double sum = 0.0;
  } reader;
  runner::Session session(DummySpec());
  session.AddObserver(reader);
  session.Initialize();
  for (auto _ : state) {
    session.Step();
    benchmark::DoNotOptimize(reader.sum);
  }
  state.counters["ns_per_step"] = benchmark::Counter(
      static_cast<double>(state.iterations()), benchmark::Counter::kIsRate | benchmark::Counter::kInvert);
}
BENCHMARK(BM_SessionStep)->Name("Runner/SessionStep/session");

BENCHMARK_CAPTURE(BM_JournalAppend, batched, io::SyncPolicy::kBatched, "batched")
    ->Name("Runner/JournalAppend/batched");
BENCHMARK_CAPTURE(BM_JournalAppend, every_row, io::SyncPolicy::kEveryRow, "every_row")
    ->Name("Runner/JournalAppend/every_row");

}  // namespace
}  // namespace hybridtest::bench
