// See run_commands.h.
#include "run_commands.h"

#include <fmt/core.h>

#include <algorithm>
#include <csignal>
#include <filesystem>

#include "resume_plan.h"
#include "hybridtest/common/error.h"
#include "hybridtest/io/config.h"
#include "hybridtest/io/run_inputs.h"
#include "hybridtest/io/run_lock.h"
#include "hybridtest/io/run_outputs.h"
#include "hybridtest/io/output_budget.h"
#include "hybridtest/io/substructure_config.h"
#include "hybridtest/runner/hybrid_test.h"
#include "hybridtest/runner/run_record.h"
#include "hybridtest/runner/stop_request.h"
#include "pre_run_checks.h"

namespace hybridtest::app {
namespace {

// SIGINT/SIGTERM ask the runner to stop after the current step (the bench holds, everything
// committed is written). The handler resets itself: a second Ctrl-C ends the process at once.
class StopOnSignal {
 public:
  StopOnSignal() {
    struct sigaction action {};
    action.sa_handler = [](int) { runner::RequestStop(); };
    action.sa_flags = SA_RESETHAND;
    sigemptyset(&action.sa_mask);
    sigaction(SIGINT, &action, &old_int_);
    sigaction(SIGTERM, &action, &old_term_);
  }
  ~StopOnSignal() {
    sigaction(SIGINT, &old_int_, nullptr);
    sigaction(SIGTERM, &old_term_, nullptr);
    runner::ClearStopRequest();
  }
  StopOnSignal(const StopOnSignal&) = delete;
  StopOnSignal& operator=(const StopOnSignal&) = delete;

 private:
  struct sigaction old_int_ {};
  struct sigaction old_term_ {};
};

}  // namespace

namespace {

// The loop and the summary, shared by run, simulate and resume.
void RunAndReport(const io::SimulationConfig& cfg, runner::SubstructureList subs,
                  runner::RunOptions run, bool quiet) {
  // A file-size limit makes a write fail (EFBIG, reported with the run's status) instead of
  // killing the process mid-row.
  std::signal(SIGXFSZ, SIG_IGN);
  if (quiet || cfg.quiet) run.progress.mode = runner::ProgressMode::kQuiet;
  runner::HybridTest test(cfg, std::move(subs), run);
  const StopOnSignal stop_on_signal;
  const runner::RunStatistics s = test.Run();
  if (quiet) return;
  fmt::print("hybridtest {}: {} steps with {}, t = {} s, {} rows -> {}\n", run.command, s.steps,
             cfg.scheme.kind == schemes::SchemeKind::kRungeKutta
                 ? fmt::format("{} ({} stages) at {} s", cfg.tableau.name, cfg.tableau.stages(), cfg.dt)
                 : schemes::SchemeKindName(cfg.scheme.kind) +
                       (cfg.scheme.adaptive.enabled ? " (adaptive step)" : fmt::format(" at {} s", cfg.dt)),
             s.sim_time, s.rows, run.csv_path);
  fmt::print("  wall time {:.3f} s ({:.3g}x real time)", s.wall_time, s.wall_slowdown);
  if (s.physical_evaluations > 0) {
    fmt::print("; {} physical evaluations, lab time {:.0f} s = {}h{:02}m ({:.0f}x slower than "
               "real time)", s.physical_evaluations, s.lab_time,
               static_cast<long>(s.lab_time) / 3600, (static_cast<long>(s.lab_time) % 3600) / 60,
               s.slowdown);
  }
  fmt::print("\n");
}

}  // namespace

void ExecuteRun(const RunCommandOptions& options) {
  const io::SimulationConfig cfg = io::LoadSimulationConfig(options.config);
  CheckSchemeStability(cfg);  // pre-run check: refuses a step beyond the stability limit
  auto subs = io::MakeSubstructures(
      cfg, {options.bench, options.allow_physical,
            "`simulate` is numerical only: use `hybridtest run` for a hybrid test"});
  CheckPhysicalSlotsBeforeMoving(cfg, subs);  // p0 and limits against the bench's, nothing sent
  runner::RunOptions run;
  run.csv_path = runner::ResolveOutputPath(cfg, options.out);
  run.command = options.command;
  // One master per run: the lock is taken before any file of the run is looked at or touched.
  const auto parent = std::filesystem::path(run.csv_path).parent_path();
  if (!parent.empty()) std::filesystem::create_directories(parent);
  const io::RunLock lock = io::RunLock::Acquire(run.csv_path, options.command);
  // Pre-run check: the journal and stage record must fit on the disk.
  const bool physical = std::any_of(subs.begin(), subs.end(),
                                    [](const auto& s) { return s->is_physical(); });
  io::CheckOutputFits(
      run.csv_path,
      io::EstimateOutputBytes(
          runner::MaxJournalRows(cfg), static_cast<int>(runner::JournalChannels(cfg, subs).size()),
          cfg.scheme.kind == schemes::SchemeKind::kRungeKutta ? cfg.tableau.stages() : 1,
          physical ? static_cast<int>(runner::StageChannels(cfg, subs).size()) : 0));
  // Results are never destroyed: an earlier run needs --overwrite, an input is never an output.
  io::CheckRunOutputs(run.csv_path, io::RunInputFiles(cfg), options.overwrite);
  run.inputs = io::RecordRunInputs(cfg, run.csv_path);
  RunAndReport(cfg, std::move(subs), std::move(run), options.quiet);
}

void ExecuteResume(const ResumeCommandOptions& options) {
  if (!std::filesystem::is_regular_file(options.csv)) {
    throw ConfigError(fmt::format("{}: no such journal: give the CSV of the run to resume",
                                  options.csv));
  }
  // One master per run: nothing of the run is read before the lock is held.
  const io::RunLock lock = io::RunLock::Acquire(options.csv, "resume");
  const ResumePlan plan = PlanResume(options);
  runner::RunOptions run;
  run.csv_path = options.csv;
  run.command = plan.command;
  run.resume_from = &plan.state;
  run.resume_force_tolerance =
      options.force_tolerance.value_or(plan.cfg.resume_force_tolerance.value_or(0.0));
  run.resume_record = plan.record;
  run.resume_position_tolerance =
      options.position_tolerance.value_or(plan.cfg.resume_position_tolerance.value_or(0.0));
  run.inputs = plan.state.inputs;
  auto subs = io::MakeSubstructures(
      plan.cfg, {options.bench, plan.command != "simulate",
                 "`simulate` is numerical only: use `hybridtest run` for a hybrid test"});
  if (!options.quiet) {
    fmt::print("hybridtest resume: {} from step {} (t = {} s, journal row {}); previous status: "
               "{}\n", options.csv, plan.step, plan.t, plan.state.rows - 1, plan.previous_status);
    std::fflush(stdout);
  }
  RunAndReport(plan.cfg, std::move(subs), std::move(run), options.quiet);
}

}  // namespace hybridtest::app
