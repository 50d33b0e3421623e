#pragma once
// Shared by `simulate` and `run`: load the config, build the substructures, run the loop,
// report. One code path, so a dummy hybrid test and a simulation are the same computation.
#include <optional>
#include <string>
#include <vector>

#include "live_monitor.h"

namespace hybridtest::app {

struct RunCommandOptions {
  std::string config;
  std::string out;
  std::optional<std::string> bench;
  bool quiet = false;
  bool overwrite = false;  // --overwrite: a run may replace an earlier run at the same path
  bool allow_physical = true;
  std::string command = "run";
  std::string clock;  // --clock virtual|wall for a real-time config ("" = wall)
  MonitorCliOptions monitor;  // --monitor HOST:PORT ... (live_monitor.h)
};

// Runs and prints a summary. Returns normally on success; throws on failure (after the
// journal and sidecar are written).
void ExecuteRun(const RunCommandOptions& options);

struct ResumeCommandOptions {
  std::string csv;                        // the journal of the run to continue
  std::optional<std::string> bench;       // --bench HOST:PORT
  bool quiet = false;
  std::optional<double> force_tolerance;  // --force-tolerance [N], else resume.force_tolerance
  std::optional<double> position_tolerance;  // --position-tolerance [m], else resume.position_tolerance
  bool after_safety_stop = false;         // --after-safety-stop: the operator fixed the cause
  std::vector<std::string> set;           // --set KEY=VALUE (runner/resume_changes.h)
  MonitorCliOptions monitor;              // --monitor HOST:PORT ... (live_monitor.h)
};

// `hybridtest resume`: rebuilds the run from its sidecar (config text and path, command) and
// continues it from its run state (docs/safety.md, "Resuming a run"), with the same code path
// and summary as ExecuteRun. Throws ConfigError (exit 2) if the run is completed, has no
// state, or stopped on a safety limit without --after-safety-stop.
void ExecuteResume(const ResumeCommandOptions& options);

}  // namespace hybridtest::app
