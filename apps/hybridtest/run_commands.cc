// See run_commands.h.
#include "run_commands.h"

#include <fmt/core.h>

#include <filesystem>

#include "hybridtest/io/config.h"
#include "hybridtest/io/substructure_config.h"
#include "hybridtest/runner/hybrid_test.h"

namespace hybridtest::app {

void ExecuteRun(const RunCommandOptions& options) {
  const io::SimulationConfig cfg = io::LoadSimulationConfig(options.config);
  auto subs = io::MakeSubstructures(
      cfg, {options.bench, options.allow_physical,
            "`simulate` is numerical only: use `hybridtest run` for a hybrid test"});
  runner::RunOptions run;
  run.csv_path = runner::ResolveOutputPath(cfg, options.out);
  run.command = options.command;
  if (options.quiet || cfg.quiet) run.progress.mode = runner::ProgressMode::kQuiet;
  const auto parent = std::filesystem::path(run.csv_path).parent_path();
  if (!parent.empty()) std::filesystem::create_directories(parent);
  runner::HybridTest test(cfg, std::move(subs), run);
  const runner::RunStatistics s = test.Run();
  if (options.quiet) return;
  fmt::print("hybridtest {}: {} steps of {} s with {} ({} stages), t = {} s, {} rows -> {}\n",
             options.command, s.steps, cfg.dt, cfg.tableau.name, cfg.tableau.stages(), s.sim_time,
             s.rows, run.csv_path);
  fmt::print("  wall time {:.3f} s ({:.3g}x real time)", s.wall_time, s.wall_slowdown);
  if (s.physical_evaluations > 0) {
    fmt::print("; {} physical evaluations, lab time {:.0f} s = {}h{:02}m ({:.0f}x slower than "
               "real time)", s.physical_evaluations, s.lab_time,
               static_cast<long>(s.lab_time) / 3600, (static_cast<long>(s.lab_time) % 3600) / 60,
               s.slowdown);
  }
  fmt::print("\n");
}

}  // namespace hybridtest::app
