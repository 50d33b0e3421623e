#pragma once
// What `hybridtest resume RUN.csv` continues: the run's config (the verbatim text its sidecar
// kept, read as if from its original path so that relative paths resolve as they did), its
// command, its run state, and the first entries of the resume's sidecar record. Refusals
// (docs/safety.md, "Resuming a run") throw ConfigError naming the file and the way out.
#include <nlohmann/json.hpp>

#include <optional>
#include <string>
#include <vector>

#include "hybridtest/io/config.h"
#include "hybridtest/runner/run_state.h"
#include "run_commands.h"

namespace hybridtest::app {

struct ResumePlan {
  io::SimulationConfig cfg;
  std::string command;          // "run" or "simulate"
  runner::RunState state;
  long step = 0;                // the committed step resumed from
  double t = 0.0;               // its time [s]
  std::string previous_status;  // the sidecar's status
  nlohmann::json record;        // {"previous_stop_kind", "force_tolerance_option_N"?}
  // Per slot: the commands its in-process bench had received when the run stopped (the
  // stop's record), so that a test fault that stopped it does not fire again.
  std::vector<std::optional<long>> commands_received_at_stop;
};

ResumePlan PlanResume(const ResumeCommandOptions& options);

}  // namespace hybridtest::app
