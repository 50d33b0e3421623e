#pragma once
// Shared by `simulate` and `run`: load the config, build the substructures, run the loop,
// report. One code path, so a dummy hybrid test and a simulation are the same computation.
#include <optional>
#include <string>

namespace hybridtest::app {

struct RunCommandOptions {
  std::string config;
  std::string out;
  std::optional<std::string> bench;
  bool quiet = false;
  bool overwrite = false;  // --overwrite: a run may replace an earlier run at the same path
  bool allow_physical = true;
  std::string command = "run";
};

// Runs and prints a summary. Returns normally on success; throws on failure (after the
// journal and sidecar are written).
void ExecuteRun(const RunCommandOptions& options);

}  // namespace hybridtest::app
